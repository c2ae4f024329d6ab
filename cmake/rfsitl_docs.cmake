# The manual pages and the bash completion, written by the program itself
# (`rfsitl man`, `rfsitl completion bash`: apps/rfsitl/docs_command.cpp) from
# the declarations --help and `rfsitl describe` print, so that there is no
# second copy to keep in step. Plugins of the builder's RFSITL_PLUGIN_PATH are
# kept out: the pages describe what is installed.
find_program(RFSITL_GZIP gzip)
set(RFSITL_DOCS_DIR ${PROJECT_BINARY_DIR}/docs)
set(RFSITL_DOCS_STAMP ${RFSITL_DOCS_DIR}/generated.stamp)
set(RFSITL_RUN_SELF ${CMAKE_COMMAND} -E env --unset=RFSITL_PLUGIN_PATH $<TARGET_FILE:rfsitl>)
# Man pages are installed compressed (as Debian's policy wants) when gzip is
# there; -n keeps the archive free of a time stamp, for reproducible packages.
set(RFSITL_COMPRESS_MAN "")
if(RFSITL_GZIP)
  set(RFSITL_COMPRESS_MAN COMMAND sh -c "${RFSITL_GZIP} -9nf ${RFSITL_DOCS_DIR}/man/*")
endif()
add_custom_command(OUTPUT ${RFSITL_DOCS_STAMP}
  COMMAND ${CMAKE_COMMAND} -E rm -rf ${RFSITL_DOCS_DIR}/man
  COMMAND ${RFSITL_RUN_SELF} man --directory ${RFSITL_DOCS_DIR}/man
  ${RFSITL_COMPRESS_MAN}
  COMMAND ${RFSITL_RUN_SELF} completion bash > ${RFSITL_DOCS_DIR}/rfsitl.bash
  COMMAND ${CMAKE_COMMAND} -E touch ${RFSITL_DOCS_STAMP}
  DEPENDS rfsitl
  COMMENT "Writing rfsitl's manual pages and bash completion")
add_custom_target(rfsitl_docs ALL DEPENDS ${RFSITL_DOCS_STAMP})

install(DIRECTORY ${RFSITL_DOCS_DIR}/man/ DESTINATION ${CMAKE_INSTALL_MANDIR}/man1
  COMPONENT program FILES_MATCHING PATTERN "*.1*")
install(DIRECTORY ${RFSITL_DOCS_DIR}/man/ DESTINATION ${CMAKE_INSTALL_MANDIR}/man7
  COMPONENT program FILES_MATCHING PATTERN "*.7*")
# bash-completion loads completions/<command> on demand, from the prefix's
# share folder (/usr and /usr/local; others through XDG_DATA_DIRS).
install(FILES ${RFSITL_DOCS_DIR}/rfsitl.bash DESTINATION
  ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME rfsitl COMPONENT program)
