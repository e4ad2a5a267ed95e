# Sanitizers apply to everything we compile, or to nothing: mixing instrumented and
# uninstrumented code hides errors.
if(CDPOWDER_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
  add_compile_definitions(_GLIBCXX_ASSERTIONS)  # bounds-checked operator[]: index bugs fail loudly
endif()

# ThreadSanitizer (the `ci-tsan` preset): the tile phases and the stages in pieces on threads,
# run by the `parallel` label. It cannot be combined with AddressSanitizer.
if(CDPOWDER_TSAN)
  if(CDPOWDER_SANITIZE)
    message(FATAL_ERROR "CDPOWDER_TSAN and CDPOWDER_SANITIZE exclude each other")
  endif()
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
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
