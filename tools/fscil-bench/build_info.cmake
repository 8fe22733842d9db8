# Run at every build (cmake -P): writes OUTPUT, a header defining FSCIL_VERSION (the project's
# VERSION) and FSCIL_SOURCE_COMMIT, the source tree's commit with "-dirty" when tracked files differ
# from it. The header is rewritten only when they change, so a binary names the commit it was built
# from, not the one checked out when it runs, and only the file that includes it recompiles.
execute_process(COMMAND git -C "${SOURCE_DIR}" rev-parse HEAD OUTPUT_VARIABLE commit
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE failed)
if(failed OR commit STREQUAL "")
  set(commit unknown)
else()
  execute_process(COMMAND git -C "${SOURCE_DIR}" status --porcelain --untracked-files=no OUTPUT_VARIABLE changes
                  ERROR_QUIET)
  if(NOT changes STREQUAL "")
    string(APPEND commit -dirty)
  endif()
endif()
set(header "#pragma once\n#define FSCIL_VERSION \"${VERSION}\"\n#define FSCIL_SOURCE_COMMIT \"${commit}\"\n")
file(CONFIGURE OUTPUT "${OUTPUT}" CONTENT "${header}" @ONLY)
