# Installing gdm: the CMake package (gdmConfig.cmake, gdmConfigVersion.cmake,
# the exported targets gdm::core, gdm::pipeline, gdm::image_io, gdm::itk),
# pkg-config files, the ITK module file, the man page of gdm and the Debian
# package (CPack). Every destination is relative to the prefix, so
# `cmake --install build --prefix P` and DESTDIR put everything below P.
include(CMakePackageConfigHelpers)

if(GDM_SHARED_LIBS)
  set(GDM_SHARED_LIBS_BOOL TRUE)
else()
  set(GDM_SHARED_LIBS_BOOL FALSE)
endif()

install(EXPORT gdmTargets NAMESPACE gdm:: DESTINATION ${GDM_INSTALL_CMAKEDIR} FILE gdmTargets.cmake)
if(TARGET gdm_image_io)
  install(EXPORT gdmImageIOTargets NAMESPACE gdm:: DESTINATION ${GDM_INSTALL_CMAKEDIR} FILE gdmImageIOTargets.cmake)
endif()
if(TARGET GeometricallyDeformedModel)
  install(EXPORT gdmItkTargets NAMESPACE gdm:: DESTINATION ${GDM_INSTALL_CMAKEDIR} FILE gdmItkTargets.cmake)
endif()
configure_package_config_file(cmake/gdmConfig.cmake.in ${PROJECT_BINARY_DIR}/gdmConfig.cmake
  INSTALL_DESTINATION ${GDM_INSTALL_CMAKEDIR})
# 0.x: a minor version may break the API, so only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/gdmConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/gdmConfig.cmake ${PROJECT_BINARY_DIR}/gdmConfigVersion.cmake
  DESTINATION ${GDM_INSTALL_CMAKEDIR})

# pkg-config, relocatable (prefix relative to the .pc file's folder).
file(RELATIVE_PATH GDM_PC_TO_PREFIX "/p/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/p")
string(REGEX REPLACE "/$" "" GDM_PC_TO_PREFIX "${GDM_PC_TO_PREFIX}")
configure_file(cmake/gdm-core.pc.in ${PROJECT_BINARY_DIR}/gdm-core.pc @ONLY)
configure_file(cmake/gdm-pipeline.pc.in ${PROJECT_BINARY_DIR}/gdm-pipeline.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/gdm-core.pc ${PROJECT_BINARY_DIR}/gdm-pipeline.pc
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

if(TARGET GeometricallyDeformedModel AND GDM_ITK_VERSION)
  # ITK's module folder is fixed inside ITK's install (ITKConfig.cmake:
  # ITK_MODULES_DIR = <ITK prefix>/lib/cmake/ITK-x.y/Modules): this file only
  # takes effect when gdm is installed in ITK's prefix (the .deb, /usr).
  configure_file(cmake/GeometricallyDeformedModel-ITKModule.cmake.in
    ${PROJECT_BINARY_DIR}/GeometricallyDeformedModel.cmake @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/GeometricallyDeformedModel.cmake
    DESTINATION lib/cmake/ITK-${GDM_ITK_VERSION}/Modules)
endif()

# The man page of gdm, generated from `gdm --help` (cmake/help2man.cmake).
if(TARGET gdm)
  set(_gdm_man ${PROJECT_BINARY_DIR}/man/gdm.1)
  add_custom_command(OUTPUT ${_gdm_man}.gz
    COMMAND ${CMAKE_COMMAND} -D GDM=$<TARGET_FILE:gdm> -D OUTPUT=${_gdm_man} -D VERSION=${PROJECT_VERSION}
            -P ${PROJECT_SOURCE_DIR}/cmake/help2man.cmake
    COMMAND gzip -9nf ${_gdm_man}
    DEPENDS gdm ${PROJECT_SOURCE_DIR}/cmake/help2man.cmake
    COMMENT "Man page of gdm from gdm --help")
  add_custom_target(gdm_man ALL DEPENDS ${_gdm_man}.gz)
  install(FILES ${_gdm_man}.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endif()

install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})

# Debian package: cpack -G DEB (from the build folder). Installs in /usr.
set(CPACK_PACKAGE_NAME gdm)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "gdm")
set(CPACK_PACKAGE_CONTACT "gdm maintainers <gdm@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Geometrically Deformed Models: closed triangle meshes from 3D volumes")
set(CPACK_PACKAGE_DESCRIPTION "gdm extracts closed, 2-manifold, self-intersection-free triangle meshes of
objects in CT, MRI and industrial CT volumes with Geometrically Deformed Models
(Miller et al., SIGGRAPH 1991). This package holds the gdm command, the shared
libraries gdm_core, gdm_pipeline and gdm_image_io, their headers, the CMake package
(find_package(gdm COMPONENTS itk)), pkg-config files, the ITK filter, the
MeshLab 2020.09 filter plugin and the phantom.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # gdm_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)  # Depends from dpkg-shlibdeps
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS "${PROJECT_BINARY_DIR}/common;${PROJECT_BINARY_DIR}/itk-module/io")
# The headers and the CMake package name the -dev packages of what they include.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libeigen3-dev, libopenmesh-dev, libinsighttoolkit5-dev, meshlab")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_STRIP_FILES ON)
include(CPack)
