# Runs COMMAND (a ;-list) and checks its exit code and that its output matches every regex
# in PATTERNS (a ;-list). Used for command-line tests: exit codes 0/1/2 and the messages.
separate_arguments(command NATIVE_COMMAND "${COMMAND}")
if(CLEAN)  # an output folder from an earlier run would be resumed, not recomputed
  file(REMOVE_RECURSE "${CLEAN}")
endif()
execute_process(COMMAND ${command} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err
                WORKING_DIRECTORY "${WORKDIR}")
set(all "${out}${err}")
if(NOT code STREQUAL "${EXPECTED_EXIT}")
  message(FATAL_ERROR "exit code ${code}, expected ${EXPECTED_EXIT}\n--- output ---\n${all}")
endif()
foreach(pattern IN LISTS PATTERNS)
  if(NOT all MATCHES "${pattern}")
    message(FATAL_ERROR "output does not match '${pattern}'\n--- output ---\n${all}")
  endif()
endforeach()
string(REGEX MATCHALL "\n" lines "${all}")
list(LENGTH lines line_count)
if(DEFINED MAX_LINES AND line_count GREATER MAX_LINES)
  message(FATAL_ERROR "output has ${line_count} lines, more than one screen (${MAX_LINES})\n${all}")
endif()
message(STATUS "ok (exit ${code})\n${all}")
