# --- python: the octrace module (pybind11), built into build/python/ ---------------------------
# PYTHONPATH=build/python /usr/bin/python3 -c 'import octrace' after a build; `cmake --install`
# puts it under lib/python3.X/dist-packages of the prefix (site-packages for a Python without
# Debian's layout). Debian's pybind11 (pybind11-dev) and
# Python 3 with numpy; OCT_PYTHON (top CMakeLists.txt) is on by default when pybind11 is found.
# The interpreter is Debian's /usr/bin/python3 when present (the one with Debian's numpy and
# pytest), not whichever python3 comes first on PATH; -DOCT_PYTHON_EXECUTABLE=... picks another.
if(NOT OCT_PYTHON)
  return()
endif()

file(GLOB OCT_PYTHON_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/python/*.cpp)
# NO_EXTRAS: no link-time optimisation or stripping (the work is in the static libraries).
pybind11_add_module(octrace_python MODULE NO_EXTRAS ${OCT_PYTHON_SOURCES})
target_link_libraries(octrace_python PRIVATE octrace_validation octrace_teach)
set_target_properties(octrace_python PROPERTIES OUTPUT_NAME octrace
                      LIBRARY_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/python)
# The type stubs for editors, beside the module.
configure_file(${PROJECT_SOURCE_DIR}/python/octrace.pyi ${PROJECT_BINARY_DIR}/python/octrace.pyi
               COPYONLY)

# Under the prefix where the interpreter looks: Debian's python3 searches
# PREFIX/lib/python3.X/dist-packages for /usr/local (site-packages is upstream's name).
execute_process(COMMAND ${Python_EXECUTABLE} -c
                "import sys; print('dist' if any(p.endswith('dist-packages') for p in sys.path) else 'site')"
                OUTPUT_VARIABLE OCT_PYTHON_PACKAGES OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT OCT_PYTHON_PACKAGES)
  set(OCT_PYTHON_PACKAGES site)
endif()
set(OCT_PYTHON_INSTALL_DIR
    "lib/python${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}/${OCT_PYTHON_PACKAGES}-packages"
    CACHE STRING "Where cmake --install puts the octrace module, under the prefix")
install(TARGETS octrace_python LIBRARY DESTINATION ${OCT_PYTHON_INSTALL_DIR})
install(FILES ${PROJECT_SOURCE_DIR}/python/octrace.pyi DESTINATION ${OCT_PYTHON_INSTALL_DIR})

# The pytest suite (tests/python/), one CTest test per file, label e2e: the files compare the
# module's results with the octrace binary's files.
if(BUILD_TESTING)
  file(GLOB OCT_PYTHON_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tests/python/test_*.py)
  foreach(test_file IN LISTS OCT_PYTHON_TESTS)
    get_filename_component(stem ${test_file} NAME_WE)
    add_test(NAME Python.${stem}
             COMMAND ${Python_EXECUTABLE} -m pytest -q -p no:cacheprovider ${test_file}
             WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    set_tests_properties(Python.${stem} PROPERTIES
      LABELS "e2e;python"
      ENVIRONMENT "PYTHONPATH=${PROJECT_BINARY_DIR}/python;OCTRACE_BIN=$<TARGET_FILE:octrace>;OCT_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
  endforeach()
endif()
