# The package test (Package.ConsumerBuildsAndCertifiesAgainstAnInstall, tests/CMakeLists.txt):
# installs the build into a fresh prefix, checks what was installed, then configures, builds
# and runs examples/consumer against that prefix with find_package(octrace), as a project
# outside the repository would. Fails with the step's output on the first step that fails.
# Usage: cmake -DBUILD=build -DSOURCE=. -DWORK=DIR -DGENERATOR=G -DCXX=c++ [-DLAUNCHER=ccache]
#              [-DCONFIG=Release] [-DPYTHON=/usr/bin/python3 -DPYTHON_DIR=lib/python3.11/...]
#              -P tests/package/consumer_test.cmake
foreach(var BUILD SOURCE WORK GENERATOR CXX)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "consumer_test: -D${var}=... is missing (see the usage at the top)")
  endif()
endforeach()
if(NOT CONFIG)
  set(CONFIG Release)
endif()

# Runs a step; on failure stops naming it, with everything it printed.
function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer_test: ${what} failed (exit ${rc}):\n${out}")
  endif()
  message(STATUS "consumer_test: ${what}: ok")
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

# A fresh prefix and consumer build on every run: nothing left from an earlier install counts.
set(prefix ${WORK}/prefix)
set(consumer ${WORK}/consumer-build)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

step("cmake --install" ${CMAKE_COMMAND} --install ${BUILD} --prefix ${prefix} --config ${CONFIG})

# What was installed: the config, the façade, no command-line or test code, no header that
# includes CLI11 or GoogleTest (they are not dependencies of the package).
foreach(f lib/cmake/octrace/octraceConfig.cmake lib/cmake/octrace/octraceConfigVersion.cmake
          lib/cmake/octrace/octraceTargets.cmake include/octrace/certify.h
          include/octrace/core/scene/scene.h include/octrace/validation/certify_run.h bin/octrace)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "consumer_test: the install has no ${f} (cmake/install.cmake)")
  endif()
endforeach()
foreach(folder apps teach bench tests)
  if(EXISTS ${prefix}/include/octrace/${folder})
    message(FATAL_ERROR "consumer_test: ${folder}/ was installed under include/octrace; only "
                        "the libraries' headers belong in the package")
  endif()
endforeach()
file(GLOB_RECURSE headers ${prefix}/include/*)
foreach(h IN LISTS headers)
  if(NOT h MATCHES "\\.h$")
    message(FATAL_ERROR "consumer_test: ${h} was installed; only .h headers belong there")
  endif()
  file(STRINGS ${h} bad REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"](CLI/|gtest/|gmock/|benchmark/)")
  if(bad)
    message(FATAL_ERROR "consumer_test: the installed ${h} includes ${bad}: the package must "
                        "not need CLI11, GoogleTest or Google Benchmark")
  endif()
endforeach()
# The installed command line runs from the prefix (its RPATH finds CUDA's runtime).
step("running the installed octrace" ${prefix}/bin/octrace list)
list(LENGTH headers n)
message(STATUS "consumer_test: ${n} headers installed, none including CLI11 or GoogleTest")

set(launcher "")
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
step("configuring examples/consumer with CMAKE_PREFIX_PATH=${prefix}"
     ${CMAKE_COMMAND} -S ${SOURCE}/examples/consumer -B ${consumer} -G ${GENERATOR}
     -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=${CONFIG} -DCMAKE_CXX_COMPILER=${CXX}
     ${launcher} -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)

# The consumer compiles against the façade alone: the prefix's include/, not the internals'
# include/octrace (octrace::api links the libraries PRIVATE).
file(READ ${consumer}/compile_commands.json commands)
string(FIND "${commands}" "${prefix}/include/octrace" internals)
if(NOT internals EQUAL -1)
  message(FATAL_ERROR "consumer_test: the consumer compiles with ${prefix}/include/octrace on "
                      "its include path; octrace::api must give only <octrace/certify.h>:\n"
                      "${commands}")
endif()

step("building examples/consumer" ${CMAKE_COMMAND} --build ${consumer} --config ${CONFIG})
find_program(program consumer PATHS ${consumer} ${consumer}/${CONFIG} NO_DEFAULT_PATH
             NO_CACHE REQUIRED)
step("running ${program} ${SOURCE}/meshes/teapot.obj" ${program} ${SOURCE}/meshes/teapot.obj)
message(STATUS "${step_output}")

# The Python module as installed: imported from the prefix (not from the build tree), and one
# scene traced through it.
if(PYTHON)
  set(module_dir ${prefix}/${PYTHON_DIR})
  step("importing the installed octrace module from ${module_dir}"
       ${CMAKE_COMMAND} -E env PYTHONPATH=${module_dir} ${PYTHON} -c
       "import octrace, sys; assert octrace.__file__.startswith(sys.argv[1]), octrace.__file__; s = octrace.Scene(sys.argv[2]); print(s, octrace.__version__)"
       ${module_dir} ${SOURCE}/meshes/teapot.obj)
  if(NOT EXISTS ${module_dir}/octrace.pyi)
    message(FATAL_ERROR "consumer_test: the install has no ${PYTHON_DIR}/octrace.pyi (python/python.cmake)")
  endif()
endif()
