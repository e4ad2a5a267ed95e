# Installs the build tree BUILD_DIR into a scratch prefix, builds tests/package against it
# (find_package(cdpowder CONFIG)) and runs the program on the quick example; also checks that
# the man page and the bash completion were installed.
# With -DCXX=COMPILER, also what the public header brings into a program; with -DPYTHON=…,
# that the installed Python module imports.
#   cmake -DBUILD_DIR=… -DSOURCE_DIR=… -DSCRATCH=… [-DCXX=…] [-DCXX_FLAGS=…] [-DMAN_PAGE=ON]
#         -P run_package_test.cmake
foreach(variable BUILD_DIR SOURCE_DIR SCRATCH)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "run_package_test: -D${variable}=… is required")
  endif()
endforeach()
file(REMOVE_RECURSE ${SCRATCH})
set(prefix ${SCRATCH}/prefix)

function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "run_package_test: `${ARGV}` failed (${status}):\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(file bin/cdpowder include/cdpowder/cdpowder.hpp include/cdpowder/version.hpp
             share/bash-completion/completions/cdpowder)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "run_package_test: ${file} was not installed")
  endif()
endforeach()
file(GLOB package_files ${prefix}/lib*/cmake/cdpowder/cdpowderConfigVersion.cmake)
if(NOT package_files)
  message(FATAL_ERROR "run_package_test: no cdpowderConfigVersion.cmake under ${prefix}/lib*/cmake")
endif()
if(MAN_PAGE AND NOT EXISTS ${prefix}/share/man/man1/cdpowder.1)
  message(FATAL_ERROR "run_package_test: the man page was not installed")
endif()
if(MAN_PAGE)
  # help2man under a UTF-8 locale: the name line keeps its dash (it read "cdpowder ??? …")
  file(STRINGS ${prefix}/share/man/man1/cdpowder.1 name_line REGEX "^cdpowder .*contact dynamics")
  if(NOT name_line OR name_line MATCHES "\\?")
    message(FATAL_ERROR "run_package_test: the man page's NAME reads '${name_line}'")
  endif()
endif()
# the docs and examples the messages cite
foreach(file share/doc/cdpowder/config.md share/doc/cdpowder/README.md
             share/doc/cdpowder/examples/quick/scene.toml)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "run_package_test: ${file} was not installed")
  endif()
endforeach()
# the Python package, imported from the prefix's site folder (site-packages for a prefix that
# is neither /usr nor /usr/local: python/CMakeLists.txt)
if(PYTHON)
  file(GLOB site_folders ${prefix}/lib/python3*/site-packages)
  if(NOT site_folders)
    message(FATAL_ERROR "run_package_test: no lib/python3.*/site-packages under ${prefix}")
  endif()
  list(GET site_folders 0 site)
  set(ENV{PYTHONPATH} ${site})
  # (a newline, not a semicolon: CMake would split the argument there)
  run(${PYTHON} -c "import cdpowder\nprint(cdpowder.__file__, cdpowder.__version__)")
  string(FIND "${last_output}" "${site}/cdpowder" at)
  if(NOT at EQUAL 0)
    message(FATAL_ERROR "run_package_test: Python imported ${last_output}, not the installed package")
  endif()
endif()

# What <cdpowder/cdpowder.hpp> brings into a user's program: of the third-party headers only
# Eigen's, and nothing of cdpowder's internals (namespace detail)
if(DEFINED CXX)
  file(WRITE ${SCRATCH}/umbrella.cpp "#include <cdpowder/cdpowder.hpp>\n")
  execute_process(COMMAND ${CXX} -std=c++20 -H -fsyntax-only -I${prefix}/include
                          -I/usr/include/eigen3 ${SCRATCH}/umbrella.cpp
                  RESULT_VARIABLE status ERROR_VARIABLE included)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "run_package_test: <cdpowder/cdpowder.hpp> does not compile:\n${included}")
  endif()
  string(REGEX MATCHALL "[^\n ]+\\.h(pp)?" headers "${included}")
  foreach(header ${headers})
    foreach(library fmt/ toml++/ nlohmann/ CLI/ pcg_ hwy/ gtest/ benchmark/)
      string(FIND "${header}" "/${library}" at)
      if(at GREATER_EQUAL 0)
        message(FATAL_ERROR "run_package_test: <cdpowder/cdpowder.hpp> includes ${header}")
      endif()
    endforeach()
    if(header MATCHES "^${prefix}/include/cdpowder/")
      file(READ ${header} text)
      if(text MATCHES "namespace detail")
        message(FATAL_ERROR "run_package_test: <cdpowder/cdpowder.hpp> reaches ${header}, "
                            "which declares cdpowder's internals (namespace detail)")
      endif()
    endif()
  endforeach()
endif()

# the installed program runs from its prefix (a shared library found through its run path)
run(${prefix}/bin/cdpowder --version)
file(GLOB shared_libraries ${prefix}/lib*/libcdpowder_core.so* ${prefix}/lib/*/libcdpowder_core.so*)
if(shared_libraries)
  message(STATUS "run_package_test: the shared library ${shared_libraries}")
endif()

run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package -B ${SCRATCH}/build -G Ninja
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
run(${CMAKE_COMMAND} --build ${SCRATCH}/build)
run(${SCRATCH}/build/package_user ${SOURCE_DIR}/examples/quick/scene.toml)
message(STATUS "run_package_test: ${last_output}")
file(REMOVE_RECURSE ${SCRATCH})
