# `cmake --install`: the cdpowder program, the library cdpowder::core with its headers and a
# CMake package (find_package(cdpowder CONFIG), with a version file), the man page (from
# --help, when Debian's help2man is installed) and the bash completion.
include(CMakePackageConfigHelpers)

install(TARGETS cdpowder RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS cdpowder_core EXPORT cdpowderTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
# The public headers: <cdpowder/cdpowder.hpp> and every header it includes, directly or not
# (the other headers are the library's internals and stay out of a user's include folder),
# and the generated version.hpp
set(public_headers "")
set(pending cdpowder/cdpowder.hpp)
while(pending)
  list(POP_FRONT pending header)
  if(header IN_LIST public_headers)
    continue()
  endif()
  list(APPEND public_headers ${header})
  file(STRINGS ${PROJECT_SOURCE_DIR}/src/${header} includes REGEX "^#include \"cdpowder/")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^#include \"(cdpowder/[^\"]+)\".*" "\\1" included "${line}")
    if(NOT included STREQUAL "cdpowder/version.hpp")  # generated, installed below
      list(APPEND pending ${included})
    endif()
  endforeach()
endwhile()
foreach(header IN LISTS public_headers)
  get_filename_component(folder ${header} DIRECTORY)
  install(FILES ${PROJECT_SOURCE_DIR}/src/${header} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/${folder})
endforeach()
install(FILES ${PROJECT_BINARY_DIR}/src/cdpowder/generated/cdpowder/version.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cdpowder)

set(package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/cdpowder)
install(EXPORT cdpowderTargets NAMESPACE cdpowder:: DESTINATION ${package_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/cdpowderConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/cdpowderConfig.cmake
                              INSTALL_DESTINATION ${package_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cdpowderConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cdpowderConfig.cmake
              ${PROJECT_BINARY_DIR}/cdpowderConfigVersion.cmake
        DESTINATION ${package_dir})

install(FILES ${PROJECT_SOURCE_DIR}/packaging/cdpowder.bash-completion
        DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME cdpowder)

# The docs and examples that the program's messages and --help cite, beside the program.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}
        PATTERN "lab" EXCLUDE PATTERN "performance" EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/CHANGELOG.md
              ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR})

# The man page from the program's own --help (help2man), so the two never disagree.
find_program(HELP2MAN help2man)
if(HELP2MAN)
  set(man_page ${PROJECT_BINARY_DIR}/cdpowder.1)
  set(man_commands ${PROJECT_BINARY_DIR}/cdpowder_man_commands.h2m)
  add_custom_command(
    OUTPUT ${man_page}
    COMMAND ${CMAKE_COMMAND} -DCDPOWDER=$<TARGET_FILE:cdpowder> -DOUTPUT=${man_commands}
            -P ${PROJECT_SOURCE_DIR}/cmake/CdpowderManCommands.cmake
    # a UTF-8 locale (-L): help2man re-encodes --help (σ, ≤, —) to the locale's charset, and
    # under C, even with LC_ALL=C.UTF-8 set, it wrote "cdpowder ???" for the dash (measured)
    COMMAND ${HELP2MAN} -L C.UTF-8 --no-info --name "contact dynamics of cohesive powders of rigid spheres"
            --version-string ${PROJECT_VERSION} --include ${man_commands}
            --include ${PROJECT_SOURCE_DIR}/packaging/cdpowder.h2m --output ${man_page}
            $<TARGET_FILE:cdpowder>
    DEPENDS cdpowder ${PROJECT_SOURCE_DIR}/cmake/CdpowderManCommands.cmake
            ${PROJECT_SOURCE_DIR}/packaging/cdpowder.h2m
    COMMENT "Writing the man page from cdpowder --help"
    VERBATIM)
  add_custom_target(cdpowder_man_page ALL DEPENDS ${man_page})
  install(FILES ${man_page} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
else()
  message(STATUS "help2man not found: no man page (tools/install_deps.sh installs it)")
endif()
