/* softlight/softlight.h - the whole public API of libsoftlight.
 *
 *   types.h     vectors, matrices, errors
 *   image.h     float images and their files
 *   scene.h     meshes, the camera, scenes
 *   program.h   the C shader contract and the fragment built-ins
 *   texture.h   textures and samplers
 *   raster.h    draws into render targets
 *   gbuffer.h   the G-buffer
 *   renderer.h  whole frames
 *   lighting.h  the lighting-program contract and its toolbox
 *
 * Valid C11 and C++. GLSL's vocabulary (vec3, dot, normalize, dFdx, texture ...) is not part of
 * it: a C shader source opts in with #include <softlight/glsl.h>. */
#ifndef SOFTLIGHT_SOFTLIGHT_H
#define SOFTLIGHT_SOFTLIGHT_H

#include <softlight/version.h>
#include <softlight/types.h>
#include <softlight/image.h>
#include <softlight/scene.h>
#include <softlight/program.h>
#include <softlight/texture.h>
#include <softlight/raster.h>
#include <softlight/gbuffer.h>
#include <softlight/renderer.h>
#include <softlight/lighting.h>
#include <softlight/gbuffer_program.h>
#include <softlight/data.h>

#endif
