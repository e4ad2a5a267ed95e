# Sanitizers apply to everything we compile, or to nothing: mixing instrumented and
# uninstrumented code hides errors.
if(CDPOWDER_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
  add_compile_definitions(_GLIBCXX_ASSERTIONS)  # bounds-checked operator[]: index bugs fail loudly
endif()

# ThreadSanitizer (the `ci-tsan` preset): the tile phases and the stages in pieces on threads,
# run by the `parallel` label. It cannot be combined with AddressSanitizer. The threads are
# OpenMP's, whose runtime is not instrumented: clang's libomp with Archer (its OMPT tool that
# tells ThreadSanitizer what a region's barriers order) is; g++'s libgomp would report every
# barrier as a race. The runtime's own accesses are then ignored, not reported:
# TSAN_OPTIONS=ignore_noninstrumented_modules=1 (set by the preset's tests).
if(CDPOWDER_TSAN)
  if(CDPOWDER_SANITIZE)
    message(FATAL_ERROR "CDPOWDER_TSAN and CDPOWDER_SANITIZE exclude each other")
  endif()
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "CDPOWDER_TSAN needs clang with libomp and Archer (g++'s libgomp is not "
                        "instrumented): configure with the `ci-tsan` preset (Debian: apt-get "
                        "install clang libomp-dev)")
  endif()
  get_filename_component(cdpowder_clang_bin "${CMAKE_CXX_COMPILER}" REALPATH)
  get_filename_component(cdpowder_clang_bin "${cdpowder_clang_bin}" DIRECTORY)
  find_library(CDPOWDER_ARCHER_LIBRARY archer HINTS "${cdpowder_clang_bin}/../lib" REQUIRED)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  # Archer linked into every program is found by libomp without OMP_TOOL_LIBRARIES
  add_link_options(-fsanitize=thread LINKER:--no-as-needed "${CDPOWDER_ARCHER_LIBRARY}"
                   LINKER:--as-needed)
endif()

# The `fuzz` preset: clang's libFuzzer over the readers of user input (fuzz/), everything
# built with coverage for the fuzzer and the sanitizers above.
if(CDPOWDER_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "CDPOWDER_FUZZ needs clang (libFuzzer): configure with the `fuzz` preset "
                        "or -DCMAKE_CXX_COMPILER=clang++ (Debian: apt-get install clang)")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
