# ctest script: fails when golden/ differs from the commit checked out (modified, deleted or
# untracked files), so a golden rewritten by TESSERA_UPDATE_GOLDEN=1 cannot pass unnoticed:
# review the images, commit them, and this passes again.
execute_process(COMMAND ${GIT} -C ${SOURCE_DIR} status --porcelain --untracked-files=all -- golden
                OUTPUT_VARIABLE changed RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "git status failed (${rc}) in ${SOURCE_DIR}")
endif()
if(NOT changed STREQUAL "")
  message(FATAL_ERROR "golden/ differs from the commit (review and commit, or git checkout -- golden):\n${changed}")
endif()
message(STATUS "golden/ matches the commit")
