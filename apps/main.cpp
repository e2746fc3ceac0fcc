#include "apps/cli.h"

int main(int argc, char** argv) { return oct::runCli(argc, argv); }
