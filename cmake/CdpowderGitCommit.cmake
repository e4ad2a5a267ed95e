# Run at every build (not only at configure time): writes OUTPUT, a C++ file defining
# cdpowder::kGitCommit as the current commit (with "-dirty" when tracked files differ from
# it, except under results/: a sweep writing its tables there does not change the program),
# and rewrites it only when the text changes, so an unchanged commit rebuilds nothing.
# Usage: cmake -DSOURCE_DIR=… -DOUTPUT=… -P CdpowderGitCommit.cmake
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE
                ERROR_QUIET RESULT_VARIABLE result)
if(NOT result EQUAL 0 OR commit STREQUAL "")
  set(commit "unknown")
else()
  execute_process(COMMAND git diff --quiet HEAD -- . ":(exclude)results"
                  WORKING_DIRECTORY ${SOURCE_DIR}
                  RESULT_VARIABLE dirty ERROR_QUIET)
  if(NOT dirty EQUAL 0)
    string(APPEND commit "-dirty")
  endif()
endif()
string(CONCAT text "// Generated at build time by cmake/CdpowderGitCommit.cmake.\n"
       "#include \"cdpowder/version.hpp\"\n"
       "namespace cdpowder {\n"
       "const char* const kGitCommit = \"${commit}\";\n"
       "}  // namespace cdpowder\n")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
else()
  set(old "")
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUTPUT} "${text}")
endif()
