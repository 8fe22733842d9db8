# Run at every build (cmake -P): writes OUTPUT, a header defining FSCIL_SOURCE_COMMIT as the source
# tree's commit, with "-dirty" when tracked files differ from it. The header is rewritten only when
# that changes, so a binary names the commit it was built from, not the one checked out when it runs.
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
file(CONFIGURE OUTPUT "${OUTPUT}" CONTENT "#pragma once\n#define FSCIL_SOURCE_COMMIT \"${commit}\"\n" @ONLY)
