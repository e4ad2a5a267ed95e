# Every dependency comes from Debian's packages (tools/install_deps.sh installs them).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(fmt REQUIRED)
find_package(tomlplusplus REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(Threads REQUIRED)  # the workers of solver.threads
find_package(ZLIB REQUIRED)     # run.vtk_format = "zlib" (vtkZLibDataCompressor's layout)
# pcg-cpp ships headers only, without a CMake package.
find_path(PCG_INCLUDE_DIR pcg_random.hpp REQUIRED)
if(CDPOWDER_BUILD_TESTS)
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()
if(CDPOWDER_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
