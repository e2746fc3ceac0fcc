# --- teach: cost heat maps, octree overlays, `octrace explain` and its interactive page --------
# The page's script is three.js plus teach/web/src/viewer.js, bundled by esbuild, both pinned in
# teach/web/package-lock.json and installed by `npm ci` (scripts/setup). The bundle is built
# here and compiled into the library as a string, so octrace reads no node_modules at run time.
option(OCT_VIEWER "Embed the three.js viewer of `octrace explain --html` (needs teach/web/node_modules; scripts/setup runs npm ci)" ON)

set(OCT_WEB_DIR ${PROJECT_SOURCE_DIR}/teach/web)
set(OCT_VIEWER_CPP ${PROJECT_BINARY_DIR}/teach/viewer_script.cpp)
file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/teach)
if(OCT_VIEWER)
  set(OCT_ESBUILD ${OCT_WEB_DIR}/node_modules/.bin/esbuild)
  set(OCT_THREE_PACKAGE ${OCT_WEB_DIR}/node_modules/three/package.json)
  set(OCT_ESBUILD_PACKAGE ${OCT_WEB_DIR}/node_modules/esbuild/package.json)
  if(NOT EXISTS ${OCT_ESBUILD} OR NOT EXISTS ${OCT_THREE_PACKAGE}
     OR NOT EXISTS ${OCT_ESBUILD_PACKAGE})
    message(FATAL_ERROR
      "octrace: teach/web/node_modules is missing or incomplete (three.js and esbuild for "
      "`octrace explain --html`). Run scripts/setup (it runs `npm ci` in teach/web), or "
      "configure with -DOCT_VIEWER=OFF to build octrace without the HTML page.")
  endif()
  file(READ ${OCT_THREE_PACKAGE} three_json)
  string(JSON three_version GET "${three_json}" version)
  file(READ ${OCT_ESBUILD_PACKAGE} esbuild_json)
  string(JSON esbuild_version GET "${esbuild_json}" version)
  set(bundle ${PROJECT_BINARY_DIR}/teach/viewer.bundle.js)
  add_custom_command(
    OUTPUT ${bundle}
    COMMAND ${OCT_ESBUILD} ${OCT_WEB_DIR}/src/viewer.js --bundle --minify --format=iife
            --target=es2020 --log-level=warning --outfile=${bundle}
    DEPENDS ${OCT_WEB_DIR}/src/viewer.js ${OCT_WEB_DIR}/package-lock.json ${OCT_THREE_PACKAGE}
    WORKING_DIRECTORY ${OCT_WEB_DIR}
    COMMENT "Bundling the explain page (three.js ${three_version}, esbuild ${esbuild_version})"
    VERBATIM)
  add_custom_command(
    OUTPUT ${OCT_VIEWER_CPP}
    COMMAND ${CMAKE_COMMAND} -DIN=${bundle} -DOUT=${OCT_VIEWER_CPP}
            "-DVERSIONS=three ${three_version}, esbuild ${esbuild_version}"
            -P ${PROJECT_SOURCE_DIR}/teach/embed_script.cmake
    DEPENDS ${bundle} ${PROJECT_SOURCE_DIR}/teach/embed_script.cmake
    COMMENT "Embedding the explain page's script"
    VERBATIM)
else()
  message(STATUS "octrace: OCT_VIEWER=OFF, `octrace explain --html` is not available")
  configure_file(${PROJECT_SOURCE_DIR}/teach/viewer_script_off.cpp.in ${OCT_VIEWER_CPP} COPYONLY)
endif()

file(GLOB OCT_TEACH_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/teach/*.cpp)
add_library(octrace_teach STATIC ${OCT_TEACH_SOURCES} ${OCT_VIEWER_CPP})
target_link_libraries(octrace_teach PUBLIC octrace_core nlohmann_json::nlohmann_json)
