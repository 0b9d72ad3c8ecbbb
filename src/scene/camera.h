/* camera.h - the scene camera's view-projection matrix: the one matrix every stage that needs
 * the camera uses (the rasterizer, the lighting pass's inverse for background rays, the synthetic
 * G-buffers, softlight-gl's uViewProj), so they all see the same frame.
 *
 * Consumes: an sl_camera (scene.h) and the target's size in pixels.
 * Produces: proj * view with view = lookAt(eye, target, up) and proj = perspective(radians(fovy),
 * width / height, near, far), GL conventions (softlight/glsl.h: view down -Z, NDC z in [-1, 1]).
 *
 * Does not: validate the camera (the scene reader and sl_raster_scene do), or model cameras other
 * than pinhole. */
#ifndef SL_CAMERA_H
#define SL_CAMERA_H

#include <softlight/glsl.h>
#include <softlight/scene.h>

#include "scene.h"

/* sl_camera_view_proj (softlight/scene.h): view = lookAt(eye, target, up),
 * proj = perspective(radians(fovy), w/h, near, far). */

#endif
