/* scene_camera.c - the scene file's "camera" (docs/scene-format.md "camera"): the pinhole camera's
 * keys, defaults, and the checks that keep its view well defined (near and far, an up across the
 * view direction). */
#include "scene_read.h"

#include <float.h>
#include <stdio.h>

#define DEFAULT_FOVY 45.0f
#define DEFAULT_NEAR 0.1f
#define DEFAULT_FAR 100.0f
/* Far/near beyond this leaves a float depth buffer almost no precision. */
#define MAX_DEPTH_RATIO 1e7
/* Up closer than this (sine of the angle) to the view direction gives an unstable basis. */
#define MIN_UP_SINE 1e-3f

bool sl_scene_parse_camera(scene_parser *p, const cJSON *item, sl_camera *cam)
{
    static const char *const keys[] = {"eye", "target", "up", "fovy", "near", "far", NULL};
    *cam = (sl_camera){.eye = vec3(0.0f, -5.0f, 2.0f),
                       .target = vec3(0.0f, 0.0f, 0.0f),
                       .up = vec3(0.0f, 0.0f, 1.0f),
                       .fovy_deg = DEFAULT_FOVY,
                       .znear = DEFAULT_NEAR,
                       .zfar = DEFAULT_FAR};
    if (!item)
        return true;
    if (!sl_scene_check_keys(p, item, "camera", keys))
        return false;
    const cJSON *v;
    if ((v = sl_scene_member(item, "eye")) && !sl_scene_read_vec3(p, v, "camera.eye", &cam->eye))
        return false;
    if ((v = sl_scene_member(item, "target")) && !sl_scene_read_vec3(p, v, "camera.target", &cam->target))
        return false;
    if ((v = sl_scene_member(item, "up")) && !sl_scene_read_vec3(p, v, "camera.up", &cam->up))
        return false;
    if ((v = sl_scene_member(item, "fovy"))) {
        if (!sl_scene_read_float(p, v, "camera.fovy", 0.0, 180.0, &cam->fovy_deg))
            return false;
        if (cam->fovy_deg <= 0.0f || cam->fovy_deg >= 180.0f)
            return sl_scene_fail(p, "camera.fovy", SL_ERR_RANGE, "%g is outside (0, 180) degrees, exclusive",
                           (double)cam->fovy_deg);
    }
    /* near and far: any finite value here; their relations are checked below. */
    const double big = (double)FLT_MAX;
    if ((v = sl_scene_member(item, "near")) && !sl_scene_read_float(p, v, "camera.near", -big, big, &cam->znear))
        return false;
    if ((v = sl_scene_member(item, "far")) && !sl_scene_read_float(p, v, "camera.far", -big, big, &cam->zfar))
        return false;
    if (!(cam->znear > 0.0f))
        return sl_scene_fail(p, "camera.near", SL_ERR_RANGE, "%g must be greater than 0", (double)cam->znear);
    if (!(cam->zfar > cam->znear))
        return sl_scene_fail(p, "camera.far", SL_ERR_RANGE, "%g must be greater than near (%g)", (double)cam->zfar,
                       (double)cam->znear);
    if ((double)cam->zfar / (double)cam->znear > MAX_DEPTH_RATIO)
        return sl_scene_fail(p, "camera.far", SL_ERR_RANGE,
                       "far/near = %g exceeds %g; the depth buffer would lose all precision",
                       (double)cam->zfar / (double)cam->znear, MAX_DEPTH_RATIO);
    vec3 f, u;
    if (!sl_scene_safe_normalize(sub3(cam->target, cam->eye), &f))
        return sl_scene_fail(p, "camera.target", SL_ERR_RANGE,
                       "equals camera.eye (%g, %g, %g); the view direction is undefined", (double)cam->eye.x,
                       (double)cam->eye.y, (double)cam->eye.z);
    if (!sl_scene_safe_normalize(cam->up, &u))
        return sl_scene_fail(p, "camera.up", SL_ERR_RANGE, "must not be the zero vector");
    if (length3(cross(f, u)) < MIN_UP_SINE)
        return sl_scene_fail(p, "camera.up", SL_ERR_RANGE,
                       "(%g, %g, %g) is parallel to the view direction (target - eye); pick an up across it",
                       (double)cam->up.x, (double)cam->up.y, (double)cam->up.z);
    return true;
}
