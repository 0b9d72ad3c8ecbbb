# install.cmake - what `cmake --install` puts where (GNUInstallDirs paths under the prefix), in
# four components that cmake/package.cmake turns into Debian packages:
#   library      lib/libsoftlight.so.0*                         (libsoftlight0)
#   development  include/softlight/, libsoftlight.so, libsoftlight.a, lib/pkgconfig/softlight.pc,
#                lib/cmake/softlight/                           (libsoftlight-dev)
#   tools        bin/softlight, bin/softlight-gl                (softlight)
#   data         share/softlight/ (shaders/, scenes/default.json, scenes/envmaps/studio.hdr),
#                share/doc/softlight/                           (softlight-data)
# share/softlight has the source tree's layout, so that the data lookup (include/softlight/data.h)
# treats an installed prefix and a checkout alike.
include(CMakePackageConfigHelpers)

set(SL_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/softlight")
set(SL_DATA_DIR "${CMAKE_INSTALL_DATADIR}/softlight")

# ---- libraries and headers ----
install(TARGETS softlight_shared EXPORT softlightTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT library NAMELINK_COMPONENT development)
install(TARGETS softlight_lib EXPORT softlightTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development)
# The whole public include directory, whatever headers it holds.
install(DIRECTORY include/softlight DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT development
  FILES_MATCHING PATTERN "*.h")

# ---- programs ----
foreach(program softlight softlight-gl)
  if(TARGET ${program})
    install(TARGETS ${program} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
  endif()
endforeach()

# ---- data: the GLSL shaders, the default scene and the environment it and a model given alone use ----
install(DIRECTORY shaders DESTINATION ${SL_DATA_DIR} COMPONENT data)
install(FILES scenes/default.json DESTINATION ${SL_DATA_DIR}/scenes COMPONENT data)
install(FILES scenes/envmaps/studio.hdr scenes/envmaps/LICENSE-source.txt
  DESTINATION ${SL_DATA_DIR}/scenes/envmaps COMPONENT data)
install(FILES LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT data)

# ---- the CMake package: find_package(softlight) -> softlight::softlight, softlight::softlight_static ----
install(EXPORT softlightTargets NAMESPACE softlight:: DESTINATION ${SL_CMAKE_DIR} COMPONENT development)
configure_package_config_file(cmake/softlightConfig.cmake.in
  "${CMAKE_CURRENT_BINARY_DIR}/softlightConfig.cmake" INSTALL_DESTINATION ${SL_CMAKE_DIR})
# 0.x: a minor release may break the API, so only the same major.minor is compatible.
write_basic_package_version_file("${CMAKE_CURRENT_BINARY_DIR}/softlightConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/softlightConfig.cmake"
  "${CMAKE_CURRENT_BINARY_DIR}/softlightConfigVersion.cmake"
  DESTINATION ${SL_CMAKE_DIR} COMPONENT development)

# ---- softlight.pc ----
# Written at install time, so that its prefix is the one installed into (cmake --install --prefix,
# or /usr in the Debian packages) rather than the one configured.
string(REPLACE ";" " " SL_PC_OPENMP "${OpenMP_C_FLAGS}")
set(SL_PC_DL "")
if(CMAKE_DL_LIBS)
  set(SL_PC_DL "-l${CMAKE_DL_LIBS}")
endif()
configure_file(cmake/softlight.pc.in "${CMAKE_CURRENT_BINARY_DIR}/softlight.pc.in" @ONLY)
install(CODE "
  file(READ \"${CMAKE_CURRENT_BINARY_DIR}/softlight.pc.in\" _sl_pc)
  string(REPLACE \"%PREFIX%\" \"\${CMAKE_INSTALL_PREFIX}\" _sl_pc \"\${_sl_pc}\")
  file(WRITE \"${CMAKE_CURRENT_BINARY_DIR}/softlight.pc\" \"\${_sl_pc}\")"
  COMPONENT development)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/softlight.pc"
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT development)
