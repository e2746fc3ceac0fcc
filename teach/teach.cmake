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

# --- the page's kernel: the core kernel, builder and explain compiled to WebAssembly ----------
# Debian's emscripten compiles teach/wasm/page_kernel.cpp with the core and teach sources it
# calls (the same files as the octrace binary), one object each with its header dependencies,
# linked into one script with the module inlined (-sSINGLE_FILE), embedded like the viewer.
# Without emscripten the pages fall back to their recorded pixel and say so.
find_program(OCT_EMCC emcc)
set(OCT_PAGE_KERNEL_DEFAULT OFF)
if(OCT_EMCC)
  set(OCT_PAGE_KERNEL_DEFAULT ON)
endif()
option(OCT_PAGE_KERNEL "Compile the explain page's WebAssembly kernel (needs Debian's emscripten)"
       ${OCT_PAGE_KERNEL_DEFAULT})
set(OCT_PAGE_KERNEL_CPP ${PROJECT_BINARY_DIR}/teach/page_kernel_script.cpp)
if(OCT_PAGE_KERNEL)
  if(NOT OCT_EMCC)
    message(FATAL_ERROR "octrace: OCT_PAGE_KERNEL=ON needs emcc (apt-get install emscripten, or "
                        "scripts/setup), or configure with -DOCT_PAGE_KERNEL=OFF")
  endif()
  execute_process(COMMAND ${OCT_EMCC} --version OUTPUT_VARIABLE emcc_out ERROR_QUIET)
  string(REGEX MATCH "[0-9]+\\.[0-9]+\\.[0-9]+" emcc_version "${emcc_out}")
  # Debian's emcc runs its JavaScript tools with node and finds acorn there.
  set(OCT_EMCC_RUN ${CMAKE_COMMAND} -E env NODE_PATH=/usr/share/nodejs:/usr/lib/nodejs ${OCT_EMCC})
  set(kernel_dir ${PROJECT_BINARY_DIR}/teach/wasm)
  file(MAKE_DIRECTORY ${kernel_dir})
  # nlohmann/json is header-only: the emscripten build sees that folder alone, not /usr/include.
  get_target_property(json_includes nlohmann_json::nlohmann_json INTERFACE_INCLUDE_DIRECTORIES)
  find_path(OCT_JSON_INCLUDE nlohmann/json.hpp HINTS ${json_includes})
  file(MAKE_DIRECTORY ${kernel_dir}/include)
  file(CREATE_LINK ${OCT_JSON_INCLUDE}/nlohmann ${kernel_dir}/include/nlohmann SYMBOLIC)
  set(kernel_sources
      teach/wasm/page_kernel.cpp teach/explain.cpp teach/explain_page_data.cpp
      teach/colour_map.cpp teach/svg_view.cpp teach/svg.cpp core/octree/builder.cpp core/octree/edge_bound.cpp core/octree/built_scene.cpp
      core/octree/compact_layout.cpp core/octree/exhaustive_layout.cpp
      core/octree/hash_layout.cpp core/octree/layout.cpp core/octree/layout_registry.cpp
      core/octree/linear_layout.cpp core/render/film.cpp core/scene/scene.cpp
      core/system/resources.cpp core/io/ray_file.cpp core/io/markup.cpp)
  # -fno-fast-math and no contraction: the page's floats are the host kernel's, bit for bit.
  set(kernel_flags -O2 -std=c++17 -fexceptions -ffp-contract=off -I${PROJECT_SOURCE_DIR}
                   -I${kernel_dir}/include)
  set(kernel_objects "")
  foreach(src ${kernel_sources})
    string(MAKE_C_IDENTIFIER ${src} obj_name)
    set(obj ${kernel_dir}/${obj_name}.o)
    add_custom_command(
      OUTPUT ${obj}
      COMMAND ${OCT_EMCC_RUN} ${kernel_flags} -MD -MF ${obj}.d -c ${PROJECT_SOURCE_DIR}/${src}
              -o ${obj}
      DEPENDS ${PROJECT_SOURCE_DIR}/${src}
      DEPFILE ${obj}.d
      COMMENT "emcc ${src}"
      VERBATIM)
    list(APPEND kernel_objects ${obj})
  endforeach()
  set(kernel_js ${kernel_dir}/page_kernel.js)
  add_custom_command(
    OUTPUT ${kernel_js}
    COMMAND ${OCT_EMCC_RUN} -O2 -fexceptions ${kernel_objects} -o ${kernel_js} -sSINGLE_FILE=1
            -sMODULARIZE=1 -sEXPORT_NAME=OctracePageKernel -sENVIRONMENT=web,node
            -sEXPORTED_RUNTIME_METHODS=ccall,UTF8ToString,HEAPU8 -sALLOW_MEMORY_GROWTH=1
            -sMAXIMUM_MEMORY=2GB -sEXPORTED_FUNCTIONS=_malloc,_free
            -sWASM_ASYNC_COMPILATION=0
    DEPENDS ${kernel_objects}
    COMMENT "Linking the explain page's WebAssembly kernel (emscripten ${emcc_version})"
    VERBATIM)
  add_custom_command(
    OUTPUT ${OCT_PAGE_KERNEL_CPP}
    COMMAND ${CMAKE_COMMAND} -DIN=${kernel_js} -DOUT=${OCT_PAGE_KERNEL_CPP} -DKIND=kernel
            "-DVERSIONS=emscripten ${emcc_version}"
            -P ${PROJECT_SOURCE_DIR}/teach/embed_script.cmake
    DEPENDS ${kernel_js} ${PROJECT_SOURCE_DIR}/teach/embed_script.cmake
    COMMENT "Embedding the explain page's kernel"
    VERBATIM)
else()
  message(STATUS "octrace: no emscripten (OCT_PAGE_KERNEL=OFF): explain pages show their "
                 "recorded pixel only")
  configure_file(${PROJECT_SOURCE_DIR}/teach/page_kernel_off.cpp.in ${OCT_PAGE_KERNEL_CPP}
                 COPYONLY)
endif()

file(GLOB OCT_TEACH_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/teach/*.cpp)
add_library(octrace_teach STATIC ${OCT_TEACH_SOURCES} ${OCT_VIEWER_CPP} ${OCT_PAGE_KERNEL_CPP})
target_link_libraries(octrace_teach PUBLIC octrace_core nlohmann_json::nlohmann_json)
