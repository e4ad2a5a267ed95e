# Sanitizers apply to everything we compile, or to nothing: mixing instrumented and
# uninstrumented code hides errors.
if(CDPOWDER_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
  add_compile_definitions(_GLIBCXX_ASSERTIONS)  # bounds-checked operator[]: index bugs fail loudly
endif()
