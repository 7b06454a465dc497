# CTest: check_stage_includes.cmake passes on the real tree and fails, naming both
# folders, on a copy of a stage that includes another stage's header.
#   cmake -DROOT=<source dir> -DWORK=<scratch dir> -P test_check_stage_includes.cmake
execute_process(COMMAND ${CMAKE_COMMAND} -DROOT=${ROOT} -P ${ROOT}/cmake/check_stage_includes.cmake
                RESULT_VARIABLE status ERROR_VARIABLE output)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "the source tree itself fails the check:\n${output}")
endif()

file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/stages/evaluate" "${WORK}/stages/retarget")
file(WRITE "${WORK}/stages/retarget/frame_ik.h" "#pragma once\n")
file(WRITE "${WORK}/stages/retarget/retarget.cpp" "#include \"stages/retarget/frame_ik.h\"\n")  # own folder: fine
file(WRITE "${WORK}/stages/evaluate/evaluate.cpp"
     "#include <vector>\n#include \"common/model.h\"\n#include \"stages/retarget/frame_ik.h\"\n")
execute_process(COMMAND ${CMAKE_COMMAND} -DROOT=${WORK} -P ${ROOT}/cmake/check_stage_includes.cmake
                RESULT_VARIABLE status ERROR_VARIABLE output)
if(status EQUAL 0)
  message(FATAL_ERROR "a cross-stage include passed the check")
endif()
foreach(expected "stages/evaluate/evaluate.cpp:3" "stages/evaluate includes stages/retarget/frame_ik.h")
  string(FIND "${output}" "${expected}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "the check's message lacks '${expected}':\n${output}")
  endif()
endforeach()
string(FIND "${output}" "retarget.cpp" own)
if(NOT own EQUAL -1)
  message(FATAL_ERROR "an include of the stage's own folder was reported:\n${output}")
endif()
file(REMOVE_RECURSE "${WORK}")
message(STATUS "check_stage_includes: real tree clean; a cross-stage include is refused with both folders named")
