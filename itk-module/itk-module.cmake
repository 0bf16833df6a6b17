# ITK module description of GeometricallyDeformedModel (read by ITK's module
# machinery when the module is built inside ITK or as an external module).
get_filename_component(_gdm_module_dir "${CMAKE_CURRENT_LIST_FILE}" PATH)
file(READ "${_gdm_module_dir}/README.md" DOCUMENTATION)

itk_module(GeometricallyDeformedModel
  DEPENDS
    ITKCommon
    ITKMesh
    ITKQuadEdgeMesh
  TEST_DEPENDS
    ITKTestKernel
    ITKGoogleTest
    ITKIOImageBase
    ITKIOMeta
    ITKIOGDCM
    ITKIOMeshBase
    ITKIOMeshVTK
    ITKSmoothing
    ITKThresholding
    ITKImageGrid
    ITKConnectedComponents
    ITKDistanceMap
  EXCLUDE_FROM_DEFAULT
  DESCRIPTION
    "${DOCUMENTATION}"
)
