# Man pages for the helper programs (digitizer-sim, -gadget, -hil), written at build time by
# Debian's help2man from each program's own --help, so a page cannot drift from the program.
# digitizer's pages come from its command tree (host/cli). Without help2man the pages are skipped.
set(DIGITIZER_MAN_DIR ${CMAKE_BINARY_DIR}/share/man/man1)
find_program(DIGITIZER_HELP2MAN help2man)

function(digitizer_helper_man_page target summary)
  if(NOT DIGITIZER_HELP2MAN OR CMAKE_CROSSCOMPILING)
    return()
  endif()
  add_custom_command(TARGET ${target} POST_BUILD
    COMMAND ${CMAKE_COMMAND} -E make_directory ${DIGITIZER_MAN_DIR}
    COMMAND ${DIGITIZER_HELP2MAN} --no-info --no-discard-stderr --version-string=${PROJECT_VERSION}
            --name=${summary} --section=1 --output=${DIGITIZER_MAN_DIR}/${target}.1 $<TARGET_FILE:${target}>
    VERBATIM)
endfunction()
