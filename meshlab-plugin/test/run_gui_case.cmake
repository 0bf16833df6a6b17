# Starts the staged MeshLab GUI under xvfb-run for a few seconds and checks
# from the dynamic loader's log that it loaded our plugin and that the plugin
# manager accepted it (it throws for filters without class or arity).
#   GUI, XVFB, PLUGIN_NAME, LOG
set(ENV{LD_DEBUG} "files")
execute_process(COMMAND "${XVFB}" -a timeout -s INT 15 "${GUI}"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
unset(ENV{LD_DEBUG})
file(WRITE "${LOG}" "${out}\n--- stderr ---\n${err}")
if(NOT "${err}${out}" MATCHES "calling init: [^\n]*${PLUGIN_NAME}")
  message(FATAL_ERROR "the GUI did not load ${PLUGIN_NAME} (exit ${rc}); see ${LOG}")
endif()
if("${err}${out}" MATCHES "Missing (class|requirements|preconditions|postcondition|Arity) for")
  message(FATAL_ERROR "the plugin manager rejected a filter; see ${LOG}")
endif()
string(REGEX MATCH "Current Plugins Dir is: [^\n]*" dir "${err}${out}")
message(STATUS "GUI: ${dir}; ${PLUGIN_NAME} loaded and initialised (exit ${rc} after the timeout)")
