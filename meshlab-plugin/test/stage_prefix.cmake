# Stages a private MeshLab prefix that loads the freshly built plugin without
# touching /usr: copies of meshlabserver and meshlab in <prefix>/bin (their
# RUNPATH and plugin search are relative to the binary), symlinks to
# libmeshlab-common.so, to every system plugin and to our plugin.
# -D PREFIX=... -D SERVER=... -D GUI=... -D COMMON=... -D SYSTEM_PLUGINS=... -D PLUGIN=...
set(libdir "${PREFIX}/lib/x86_64-linux-gnu/meshlab")
file(MAKE_DIRECTORY "${PREFIX}/bin" "${libdir}/plugins")
foreach(exe IN ITEMS "${SERVER}" "${GUI}")
  if(EXISTS "${exe}")
    file(COPY "${exe}" DESTINATION "${PREFIX}/bin")
  endif()
endforeach()
file(CREATE_LINK "${COMMON}" "${libdir}/libmeshlab-common.so" SYMBOLIC)
file(GLOB system_plugins "${SYSTEM_PLUGINS}/*.so")
get_filename_component(ours "${PLUGIN}" NAME)
foreach(p IN LISTS system_plugins)
  get_filename_component(name "${p}" NAME)
  if(NOT name STREQUAL ours)
    file(CREATE_LINK "${p}" "${libdir}/plugins/${name}" SYMBOLIC)
  endif()
endforeach()
file(CREATE_LINK "${PLUGIN}" "${libdir}/plugins/${ours}" SYMBOLIC)
