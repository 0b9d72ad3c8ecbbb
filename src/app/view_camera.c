/* view_camera.c - the viewer's orbit camera (see view_internal.h).
 *
 * World space is Z-up (docs/conventions.md "Coordinate frames"), so orbiting turns the eye
 * about the +Z axis through the target and tilts it in elevation; up stays +Z once the user has moved. The scene's camera is
 * kept untouched as "home" so that the first frame, and every frame after a reset, is the very
 * camera `softlight render` uses (the viewer's end-to-end test compares the two). */
#include "view_internal.h"

#include <math.h>

/* The orbit form of the home camera. When the home camera looks straight down or up the
 * azimuth is undefined; it is then chosen so that the scene's up vector stays the top of the
 * image (eye on the side opposite to `up`, as seen from above). */
static void orbit_from(view_camera *c, const sl_camera *cam)
{
    vec3 offset = sub(cam->eye, cam->target);
    float dist = length(offset);
    if (!(dist > 1e-6f) || !isfinite(dist)) {
        offset = vec3(0.0f, -1.0f, 0.0f);
        dist = 1.0f;
    }
    c->target = cam->target;
    c->distance = dist;
    float horizontal = sqrtf(offset.x * offset.x + offset.y * offset.y);
    c->elevation_deg = degrees(atan2f(offset.z, horizontal));
    if (horizontal > 1e-4f * dist)
        c->azimuth_deg = degrees(atan2f(offset.y, offset.x));
    else
        c->azimuth_deg = degrees(atan2f(-cam->up.y, -cam->up.x));
    c->elevation_deg = clampf(c->elevation_deg, -VIEW_MAX_ELEVATION, VIEW_MAX_ELEVATION);
}

/* Rebuild `cam` from the orbit form. Near and far scale with the distance (near only down, far
 * only up), so zooming in never clips the object and zooming out never cuts the far side. */
static void update(view_camera *c)
{
    float az = radians(c->azimuth_deg), el = radians(c->elevation_deg);
    vec3 dir = vec3(cosf(el) * cosf(az), cosf(el) * sinf(az), sinf(el));
    float ratio = c->distance / c->home_distance;
    c->cam = c->home;
    c->cam.target = c->target;
    c->cam.eye = add(c->target, scale(dir, c->distance));
    c->cam.up = vec3(0.0f, 0.0f, 1.0f);
    c->cam.znear = c->home.znear * minf(1.0f, ratio);
    c->cam.zfar = c->home.zfar * maxf(1.0f, ratio);
    c->at_home = false;
}

static void leave_home(view_camera *c)
{
    if (c->at_home)
        orbit_from(c, &c->home);
}

void view_camera_init(view_camera *c, const sl_camera *home)
{
    c->home = *home;
    orbit_from(c, home);
    c->home_distance = c->distance;
    view_camera_reset(c);
}

void view_camera_reset(view_camera *c)
{
    c->cam = c->home;
    c->at_home = true;
}

void view_camera_orbit(view_camera *c, float d_azimuth_deg, float d_elevation_deg)
{
    leave_home(c);
    c->azimuth_deg = fmodf(c->azimuth_deg + d_azimuth_deg, 360.0f);
    c->elevation_deg = clampf(c->elevation_deg + d_elevation_deg, -VIEW_MAX_ELEVATION, VIEW_MAX_ELEVATION);
    update(c);
}

void view_camera_pan(view_camera *c, float dx, float dy)
{
    leave_home(c);
    update(c); /* cam now holds the orbit form's eye, from which right and up follow */
    vec3 forward = normalize(sub(c->cam.target, c->cam.eye));
    vec3 right = normalize(cross(forward, c->cam.up));
    vec3 up = cross(right, forward);
    /* The image is 2 tan(fovy/2) * distance tall at the target's depth. */
    float height = 2.0f * c->distance * tanf(radians(c->home.fovy_deg) * 0.5f);
    c->target = add(c->target, add(scale(right, -dx * height), scale(up, dy * height)));
    update(c);
}

void view_camera_zoom(view_camera *c, float factor)
{
    leave_home(c);
    c->distance = clampf(c->distance * factor, 1e-4f * c->home_distance, 1e4f * c->home_distance);
    update(c);
}
