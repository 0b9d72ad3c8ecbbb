/* toon_lighting.c - your own lighting function over softlight's G-buffer.
 *
 * softlight rasterizes a scene into its G-buffer (sl_raster_scene: position, normal, diffuse and
 * specular colour, lobe and depth per pixel); this program then lights every texel itself with
 * a toon shader: three flat diffuse bands, a hard Blinn-Phong highlight, a rim light, and ink
 * outlines where the normal or the distance jumps between neighbouring texels.
 *
 *   toon_lighting OUT.png [WIDTHxHEIGHT] [SCENE.json or MODEL]
 *
 * The scene defaults to softlight's scenes/default.json (a chart of spheres). */
#include <math.h>
#include <stdio.h>

#include <softlight/glsl.h>
#include <softlight/softlight.h>

/* Is the texel at (x, y) on an outline: beside an empty texel, a crease or a jump in distance? */
static bool outline(const sl_gbuffer *gb, int x, int y, vec3 eye)
{
    const sl_gbuffer_texel *t = &gb->texels[(size_t)y * (size_t)gb->width + (size_t)x];
    float dist = length(sub(t->position, eye));
    const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
    for (int i = 0; i < 4; i++) {
        int nx = x + dx[i], ny = y + dy[i];
        if (nx < 0 || ny < 0 || nx >= gb->width || ny >= gb->height)
            continue;
        const sl_gbuffer_texel *o = &gb->texels[(size_t)ny * (size_t)gb->width + (size_t)nx];
        if (o->depth >= 1.0f || dot(t->normal, o->normal) < 0.6f ||
            length(sub(o->position, eye)) - dist > 0.02f * dist)
            return true;
    }
    return false;
}

/* The lighting function: one covered texel's colour, seen from `eye`, lit from direction l. */
static vec3 toon(const sl_gbuffer_texel *t, vec3 eye, vec3 l)
{
    vec3 v = normalize(sub(eye, t->position));
    vec3 n = dot(t->normal, v) < 0.0f ? scale(t->normal, -1.0f) : t->normal;
    vec3 base = clamp(add(t->kd, scale(t->ks, 0.6f)), 0.0f, 1.0f);
    float d = dot(n, l);
    float band = d > 0.55f ? 1.0f : d > 0.1f ? 0.6f : 0.3f;
    /* the lobe: a Phong exponent, or GGX roughness r (alpha = -1 - r) taken as 2 / r^2 - 2 */
    float r = -1.0f - t->alpha, shininess = t->alpha >= 0.0f ? t->alpha : 2.0f / maxf(r * r, 1e-3f) - 2.0f;
    float spec = powf(maxf(dot(n, normalize(add(l, v))), 0.0f), clampf(shininess, 20.0f, 400.0f));
    float rim = powf(1.0f - maxf(dot(n, v), 0.0f), 3.0f);
    vec3 c = scale(base, band);
    if (d > 0.0f && spec > 0.5f)
        c = mix(c, vec3s(1.0f), 0.8f);
    if (rim > 0.45f)
        c = add(c, vec3s(0.15f));
    return c;
}

int main(int argc, char **argv)
{
    int w = 320, h = 180;
    char path[4096] = "";
    if (argc < 2 || argc > 4 || (argc > 2 && sscanf(argv[2], "%dx%d", &w, &h) != 2)) {
        fprintf(stderr, "usage: toon_lighting OUT.png [WIDTHxHEIGHT] [SCENE.json or MODEL]\n");
        return 2;
    }
    if (argc > 3)
        snprintf(path, sizeof path, "%s", argv[3]);
    else if (!sl_data_path("scenes/default.json", path, sizeof path)) {
        fprintf(stderr, "toon_lighting: no softlight data directory (set SOFTLIGHT_DATA_DIR)\n");
        return 1;
    }
    sl_error err = {0};
    sl_gbuffer gb = {0};
    sl_image img = {0};
    sl_scene *scene = sl_scene_open(path, &err);
    sl_raster *raster = scene ? sl_raster_create(&(sl_raster_desc){.threads = 0}, &err) : NULL;
    sl_camera cam = scene ? sl_scene_camera(scene) : (sl_camera){0};
    bool ok = raster && sl_gbuffer_resize(&gb, w, h, &err) && sl_raster_scene(raster, scene, &cam, &gb, &err) &&
              sl_image_alloc(&img, w, h, 3, &err);

    /* The key light: from behind the camera, above and to its left. */
    vec3 f = normalize(sub(cam.target, cam.eye)), right = normalize(cross(f, cam.up)), up = cross(right, f);
    vec3 l = normalize(add(add(scale(f, -0.6f), scale(right, -0.5f)), scale(up, 0.8f)));
    for (int y = 0; ok && y < h; y++) /* G-buffer row 0 is the bottom, image row 0 the top */
        for (int x = 0; x < w; x++) {
            const sl_gbuffer_texel *t = &gb.texels[(size_t)y * (size_t)w + (size_t)x];
            vec3 c = t->depth >= 1.0f        ? mix(vec3(0.93f, 0.9f, 0.82f), vec3(0.7f, 0.8f, 0.9f), (float)y / (float)h)
                     : outline(&gb, x, y, cam.eye) ? vec3s(0.05f)
                                              : toon(t, cam.eye, l);
            float *px = &img.data[((size_t)(h - 1 - y) * (size_t)w + (size_t)x) * 3];
            px[0] = clampf(c.x, 0.0f, 1.0f), px[1] = clampf(c.y, 0.0f, 1.0f), px[2] = clampf(c.z, 0.0f, 1.0f);
        }
    ok = ok && sl_image_write_png(argv[1], &img, &err);
    if (!ok)
        fprintf(stderr, "toon_lighting: %s\n", err.msg);
    sl_image_free(&img);
    sl_gbuffer_free(&gb);
    sl_raster_destroy(raster);
    sl_scene_close(scene);
    return ok ? 0 : 1;
}
