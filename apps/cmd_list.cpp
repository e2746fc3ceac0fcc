// octrace list: what this build offers at each extension point, read from the lists themselves
// (the layout registry, the backend list), so scripts iterate them instead of spelling them out.
#include <cstdio>

#include "apps/cli.h"

namespace oct {
namespace {

struct ListOptions {
    std::string what = "all";
    bool names = false;
};

void runList(const ListOptions& o) {
    const bool all = o.what == "all";
    if (all || o.what == "layouts") {
        if (!o.names) std::printf("layouts (--accel):\n");
        for (const LayoutDesc& l : layouts())
            o.names ? std::printf("%s\n", l.name) : std::printf("  %-12s %s\n", l.name, l.summary);
    }
    if (all || o.what == "backends") {
        if (!o.names) std::printf("backends (--backend):\n");
        for (const BackendDesc& b : backends()) {
            if (o.names) {
                std::printf("%s\n", b.name);
                continue;
            }
            std::string why;
            const bool here = b.available(why);
            std::printf("  %-12s %s [%s: %s]\n", b.name, b.summary, here ? "available" : "not here",
                        why.c_str());
        }
    }
}

}  // namespace

void registerList(CLI::App& app) {
    auto o = std::make_shared<ListOptions>();
    CLI::App* cmd = app.add_subcommand(
        "list", "List the layouts and backends this build offers (from their registries)");
    cmd->add_option("what", o->what, "layouts, backends or all")
        ->capture_default_str()
        ->check(CLI::IsMember({"all", "layouts", "backends"}));
    cmd->add_flag("--names", o->names, "Names only, one per line (for scripts)");
    cmd->callback([o] { runList(*o); });
}

}  // namespace oct
