/* camera.c - the scene camera's view-projection matrix (camera.h). */
#include "camera.h"

mat4 sl_camera_view_proj(const sl_camera *cam, int width, int height)
{
    mat4 view = lookAt(cam->eye, cam->target, cam->up);
    mat4 proj = perspective(radians(cam->fovy_deg), (float)width / (float)height, cam->znear, cam->zfar);
    return mat4_mul(proj, view);
}
