# Writes OUTPUT, a help2man include file with a COMMANDS section: every command's own --help,
# so the man page covers the options of each command (help2man reads only the top --help).
#   cmake -DCDPOWDER=… -DOUTPUT=… -P CdpowderManCommands.cmake
set(text "[COMMANDS]\n")
foreach(command simulate compact resume deposit sweep)
  execute_process(COMMAND ${CDPOWDER} ${command} --help OUTPUT_VARIABLE help RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "cdpowder ${command} --help failed (${status})")
  endif()
  # CLI11 prints the program as it was started: the build tree's path
  string(REPLACE "${CDPOWDER}" "cdpowder" help "${help}")
  # roff: a leading dot or quote starts a request, a backslash an escape
  string(REPLACE "\\" "\\e" help "${help}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" help "${help}")
  string(APPEND text ".SS ${command}\n.nf\n${help}.fi\n")
endforeach()
file(WRITE ${OUTPUT} "${text}")
