# package.cmake - Debian packages from the install components (cmake/install.cmake):
#   cpack -G DEB   (in the build directory; docs/install.md "Debian packages")
# libsoftlight0 (the shared library), libsoftlight-dev (headers, static library, pkg-config and
# CMake files), softlight (the programs) and softlight-data (shaders and the default scene, which
# the library and the programs look up at run time). Library dependencies are found by
# dpkg-shlibdeps; the development package names the -dev packages its static library needs.
# Configure packages with -DCMAKE_INSTALL_PREFIX=/usr -DSL_NATIVE=OFF: -march=native would tie
# them to the build machine's CPU.
set(CPACK_PACKAGE_NAME softlight)
set(CPACK_PACKAGE_VENDOR "the softlight authors")
set(CPACK_PACKAGE_CONTACT "the softlight authors <softlight@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_RESOURCE_FILE_LICENSE "${CMAKE_CURRENT_SOURCE_DIR}/LICENSE")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_COMPONENTS_ALL library development tools data)

set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON) # a shlibs file where there is a shared library
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY ">=")
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)

set(CPACK_DEBIAN_LIBRARY_PACKAGE_NAME libsoftlight${PROJECT_VERSION_MAJOR})
set(CPACK_DEBIAN_LIBRARY_PACKAGE_SECTION libs)
set(CPACK_COMPONENT_LIBRARY_DESCRIPTION "softlight's shared library: a CPU rasterizer with C shaders for image-based lighting")
set(CPACK_COMPONENT_LIBRARY_DEPENDS data)

set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_NAME libsoftlight-dev)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_DEPENDS "libcjson-dev, libassimp-dev, libopenexr-dev, libpng-dev, libjpeg-dev, pkg-config")
if(SL_HAVE_EMBREE) # libsoftlight.a then calls Embree (src/shading/visibility.c)
  string(APPEND CPACK_DEBIAN_DEVELOPMENT_PACKAGE_DEPENDS ", libembree-dev")
endif()
set(CPACK_COMPONENT_DEVELOPMENT_DESCRIPTION "softlight's headers, static library, pkg-config and CMake files")
set(CPACK_COMPONENT_DEVELOPMENT_DEPENDS library)

set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME softlight)
set(CPACK_COMPONENT_TOOLS_DESCRIPTION "softlight and softlight-gl: render scenes and models from the command line")
set(CPACK_COMPONENT_TOOLS_DEPENDS data)
# softlight-gl opens EGL through libepoxy at run time (no link-time dependency to find); the
# viewer's HUD font.
set(CPACK_DEBIAN_TOOLS_PACKAGE_RECOMMENDS "libegl1, libegl-mesa0, libgl1-mesa-dri, fonts-dejavu-core")

set(CPACK_DEBIAN_DATA_PACKAGE_NAME softlight-data)
set(CPACK_DEBIAN_DATA_PACKAGE_ARCHITECTURE all)
set(CPACK_COMPONENT_DATA_DESCRIPTION "softlight's GLSL shaders, default scene and studio environment")

include(CPack)
