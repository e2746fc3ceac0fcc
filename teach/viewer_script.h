// The explain page's script: three.js and teach/web/src/viewer.js bundled by esbuild at build
// time and compiled into the binary (the build generates viewer_script.cpp from the bundle, see
// teach/teach.cmake), so `octrace explain --html` needs no node_modules and no network.
#pragma once

#include <string>

namespace oct {

// False in a build configured with -DOCT_VIEWER=OFF (no npm packages): no --html page.
bool viewerAvailable();
// The bundled, minified script ("" without the viewer).
const std::string& viewerScript();
// "three 0.187.0, esbuild 0.28.2" (what was bundled), for the page's footer.
const char* viewerVersions();

}  // namespace oct
