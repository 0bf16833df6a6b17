# Fails when meshlab-plugin/PARAMETERS.md or meshlab-plugin/scripts/*.mlx
# differ from what the filters' parameter lists generate; says how to refresh.
#   TOOL (gdm_ml_testtool), SOURCE (meshlab-plugin/), WORK (scratch folder)
# Writes into a folder of its own: the cases' scripts in WORK have the same
# names (from_volume.mlx, ...), and overwriting them while a case reads them
# made meshlab_from_volume fail now and then under ctest -j2.
set(WORK ${WORK}/parameters-check)
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${TOOL} parameters OUTPUT_FILE ${WORK}/PARAMETERS.md RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "gdm_ml_testtool parameters failed")
endif()
file(READ ${WORK}/PARAMETERS.md generated)
file(READ ${SOURCE}/PARAMETERS.md committed)
if(NOT generated STREQUAL committed)
  message(FATAL_ERROR "meshlab-plugin/PARAMETERS.md is stale: gdm_ml_testtool parameters > meshlab-plugin/PARAMETERS.md")
endif()
foreach(filter from_volume deform_mesh shrink_wrap)
  execute_process(COMMAND ${TOOL} script ${filter} ${WORK}/${filter}.mlx RESULT_VARIABLE rc)
  file(READ ${WORK}/${filter}.mlx generated)
  file(READ ${SOURCE}/scripts/${filter}.mlx committed)
  if(NOT rc EQUAL 0 OR NOT generated STREQUAL committed)
    message(FATAL_ERROR "meshlab-plugin/scripts/${filter}.mlx is stale: gdm_ml_testtool script ${filter} meshlab-plugin/scripts/${filter}.mlx")
  endif()
endforeach()
message(STATUS "PARAMETERS.md and scripts/*.mlx match the filters' parameter lists")
