# Usage: cmake -DANALYZE=<systemd-analyze> -DUNIT=<sinewd.service> -DSINEWD=<built sinewd> -DWORK=<dir>
#          -P service_unit_test.cmake
# The shipped unit, with ExecStart pointing at the built daemon (verify
# checks that the command exists): `systemd-analyze verify` must accept it
# and `systemd-analyze security` must rate its exposure at most 2.5 ("OK";
# --threshold is on a 0..100 scale). Registered only where systemd-analyze is.
file(MAKE_DIRECTORY ${WORK})
file(READ ${UNIT} text)
string(REPLACE "/usr/bin/sinewd" "${SINEWD}" text "${text}")
file(WRITE ${WORK}/sinewd.service "${text}")
execute_process(COMMAND ${ANALYZE} verify ${WORK}/sinewd.service RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "systemd-analyze verify refused the unit (${rc}):\n${out}${err}")
endif()
execute_process(COMMAND ${ANALYZE} security --offline=true --threshold=25 ${WORK}/sinewd.service
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(REGEX MATCH "Overall exposure level[^\n]*" overall "${out}")
message("${overall}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "exposure above 2.5 (${rc}):\n${out}${err}")
endif()
