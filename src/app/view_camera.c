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

/* The nearest distance along `dir` (unit, from the target to the eye) that keeps the eye
 * outside the bounds, plus a margin of 2% of their diagonal: where the ray from the target
 * leaves the box (0 when the target is outside it), at most half the scene camera's own. */
static float min_distance(const view_camera *c, vec3 dir)
{
    if (!c->have_bounds)
        return 1e-4f * c->home_distance;
    vec3 lo = c->lo, hi = c->hi;
    float diag = length(sub(hi, lo));
    float margin = maxf(0.02f * diag, 1e-6f);
    const float o[3] = {c->target.x, c->target.y, c->target.z}, d[3] = {dir.x, dir.y, dir.z};
    const float l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
    float t_exit = INFINITY;
    for (int i = 0; i < 3; i++) {
        if (o[i] < l[i] || o[i] > h[i])
            return margin; /* the target is outside the box */
        if (d[i] > 1e-9f)
            t_exit = minf(t_exit, (h[i] - o[i]) / d[i]);
        else if (d[i] < -1e-9f)
            t_exit = minf(t_exit, (l[i] - o[i]) / d[i]);
    }
    /* A scene seen from inside its bounds (a room) keeps its own camera's distance reachable:
     * the limit never exceeds half of it. */
    return minf((isfinite(t_exit) ? t_exit : 0.0f) + margin, 0.5f * c->home_distance);
}

static float max_distance(const view_camera *c)
{
    if (!c->have_bounds)
        return 1e4f * c->home_distance;
    /* 10 x the framing distance at the widest aspect the window would make it shortest */
    return maxf(10.0f * view_camera_frame_distance(c, 1.0f), c->home_distance);
}

/* Rebuild `cam` from the orbit form. Near and far scale with the distance (near only down, far
 * only up), so zooming in never clips the object and zooming out never cuts the far side. */
static void update(view_camera *c)
{
    float az = radians(c->azimuth_deg), el = radians(c->elevation_deg);
    vec3 dir = vec3(cosf(el) * cosf(az), cosf(el) * sinf(az), sinf(el));
    c->distance = clampf(c->distance, min_distance(c, dir), max_distance(c));
    float ratio = c->distance / c->home_distance;
    c->cam = c->home;
    c->cam.target = c->target;
    c->cam.eye = add(c->target, scale(dir, c->distance));
    c->cam.up = vec3(0.0f, 0.0f, 1.0f);
    c->cam.znear = c->home.znear * minf(1.0f, ratio);
    c->cam.zfar = c->home.zfar * maxf(1.0f, ratio);
    if (c->have_bounds) { /* and never clip the bounding sphere (framing may go far from home) */
        float r = 0.5f * length(sub(c->hi, c->lo));
        float dc = length(sub(c->cam.eye, scale(add(c->lo, c->hi), 0.5f)));
        if (c->cam.znear > dc - r)
            c->cam.znear = maxf(minf(c->cam.znear, dc - r), dc * 1e-3f);
        c->cam.zfar = maxf(c->cam.zfar, dc + r);
    }
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
    c->distance *= factor; /* update() holds it within the limits */
    update(c);
}

void view_camera_set_bounds(view_camera *c, vec3 lo, vec3 hi)
{
    c->lo = lo;
    c->hi = hi;
    c->have_bounds = lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z && isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z);
}

float view_camera_frame_distance(const view_camera *c, float aspect)
{
    float r = maxf(0.5f * length(sub(c->hi, c->lo)), 1e-4f);
    float half_v = radians(c->home.fovy_deg) * 0.5f;
    float half_h = atanf(tanf(half_v) * (aspect > 0.0f ? aspect : 1.0f));
    float half = minf(half_v, half_h);
    return 1.05f * r / sinf(half);
}

void view_camera_frame(view_camera *c, float aspect)
{
    if (!c->have_bounds)
        return;
    leave_home(c);
    c->target = scale(add(c->lo, c->hi), 0.5f);
    c->distance = view_camera_frame_distance(c, aspect);
    update(c);
}

void view_camera_carry(view_camera *c, const view_camera *old)
{
    if (old->at_home)
        return;
    c->target = old->target;
    c->distance = old->distance;
    c->azimuth_deg = old->azimuth_deg;
    c->elevation_deg = old->elevation_deg;
    update(c);
}
