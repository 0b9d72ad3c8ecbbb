/* cmd_info.c - `softlight info scene.json`: what a scene holds and the memory a render of it
 * needs at its peak, for the render options given (the same words as `render`). */
#include <stdio.h>
#include <sys/stat.h>

#include "args.h"
#include "commands.h"
#include "core/image.h"
#include "ibl/ibl.h"
#include "ibl/texel_e5.h"
#include "raster/gbuffer.h"
#include "render_options.h"
#include "scene/scene.h"
#include "ibl/env_dist.h"
#include "shading/splitsum_lut.h"
#include "shadow/shadow.h"
#include "shadow/sky.h"

/* The memory `softlight render` holds, in bytes, phase by phase: what each stage allocates and
 * what is still held from the stages before (src/render/renderer.c's order). The peak is the
 * largest phase. Measured with /usr/bin/time -v (max RSS) against this model: within 10% for
 * environments from 1024x512 to 16384x8192 and frames up to 1920x1080 (docs/scene-format.md,
 * "Limits"). A texel of an environment level is 12 bytes (vec3). */
typedef struct {
    size_t program;          /* the executable, its libraries, thread stacks: measured */
    size_t env_load;         /* the .hdr file and its decoded image */
    size_t env_build;        /* sl_env_build: image + the mip chain (+ the odd-size filter's scratch) */
    size_t env;              /* the mip chain, held from then on */
    size_t irradiance;       /* held: an irradiance map (brute, map); SH9 is 9 colours */
    size_t irradiance_build; /* while it is built, besides the environment */
    size_t env_lights;       /* the residual's mip chain, held */
    size_t env_lights_build; /* while extracted: 48 B/texel quadrature nodes and the residual image,
                                then the residual's own sl_env_build */
    size_t env_oct;          /* --env-layout oct: the octahedral chain, held */
    size_t env_oct_build;    /* while built: the chain and its texels' solid angles (4 B each) */
    size_t splitsum;         /* --estimator splitsum: one prefiltered chain (with its compact rows) per
                                lobe set the materials use, and the BRDF table, held */
    size_t env_dist;         /* --estimator mis: the distribution (8 B a grid texel, 4 a row) and
                                its packed texels (16 B a level-0 texel), held (ibl/env_dist.h) */
    size_t shadows;          /* --shadows: the cube maps of the lights that cast (6 faces of 4-byte
                                depths) and the env lights' maps (4 B a texel); --sky-maps: the
                                sky visibility maps (4 B a texel); held */
    size_t shadows_build;    /* while drawn: one face's or map's 8-byte texels (src/shadow) */
    size_t frame;            /* G-buffer, radiance, display image, PNG encoding, mesh copies */
    size_t peak;
    const char *peak_at;
} memory_model;

#define PROGRAM_BYTES ((size_t)16 << 20) /* max RSS of a 16x16 render without environment: 15.5 MiB */

/* Texels of a W x H mip chain down to 1x1 (sl_env_build's sizes). */
static size_t chain_texels(int w, int h)
{
    size_t total = 0;
    for (;; w = w / 2 > 1 ? w / 2 : 1, h = h / 2 > 1 ? h / 2 : 1) {
        total += (size_t)w * (size_t)h;
        if (w == 1 && h == 1)
            return total;
    }
}

/* A chain that is kept: the block, and for chains of at most SL_ENV_PAIRS_MAX_TEXELS texels, with
 * `pairs` (what sl_env_build keeps; the split sum's prefiltered chains do not) the pair rows
 * (ibl.h sl_env.pairs: the chain again with one texel more a row), and the compact rows
 * (sl_env.e5: 4 bytes a texel, W + 1 a row, sl_e5_row(H, levels) rows). */
static size_t chain_held_bytes(int w, int h, bool pairs)
{
    const int w0 = w, h0 = h;
    size_t texels = chain_texels(w, h), rows = 0;
    int levels = 0;
    for (;; w = w / 2 > 1 ? w / 2 : 1, h = h / 2 > 1 ? h / 2 : 1) {
        rows += (size_t)h;
        levels++;
        if (w == 1 && h == 1)
            break;
    }
    size_t e5 = ((size_t)w0 + 1) * (size_t)sl_e5_row(h0, levels) * 4;
    return texels * 12 + (texels <= SL_ENV_PAIRS_MAX_TEXELS ? (pairs ? (texels + rows) * 12 : 0) + e5 : 0);
}

/* sl_env_build of a W x H image (the image itself not counted): the chain, level 0 converted
 * straight into it, and the general filter's scratch of mw x h rows of three doubles, allocated
 * by the first level that is not an exact halving of the one before (src/ibl/env.c). */
static size_t env_build_bytes(int w, int h)
{
    size_t scratch = 0;
    for (int lw = w, lh = h; !(lw == 1 && lh == 1);) {
        int mw = lw / 2 > 1 ? lw / 2 : 1, mh = lh / 2 > 1 ? lh / 2 : 1;
        if (lw != 2 * mw || lh != 2 * mh) {
            scratch = (size_t)mw * (size_t)lh * 24;
            break;
        }
        lw = mw;
        lh = mh;
    }
    return chain_held_bytes(w, h, true) + scratch;
}

static void phase(memory_model *m, size_t bytes, const char *what)
{
    if (bytes > m->peak) {
        m->peak = bytes;
        m->peak_at = what;
    }
}

/* Texels of the octahedral chain sl_env_build_oct makes from a lat-long chain env_w wide: S x S
 * down to 1x1, S the smallest power of two >= env_w (at most SL_ENV_OCT_MAX_SIZE). */
static size_t oct_chain_texels(int env_w)
{
    size_t s = 1, total = 0;
    while (s < (size_t)env_w && s < SL_ENV_OCT_MAX_SIZE)
        s *= 2;
    for (; s >= 1; s /= 2)
        total += s * s;
    return total;
}

/* env_w x env_h: the environment (0 x 0: none, a 1x1 black map); irr_w x irr_h: the scene's
 * irradiance map when the render reads it; file sizes as on disk; lobe_sets: how many split-sum
 * chains the materials need (sl_renderer_splitsum_sets: Phong, GGX or both). */
static memory_model model_render(const sl_render_desc *d, int env_w, int env_h, size_t env_file, int irr_w,
                                 int irr_h, size_t irr_file, size_t mesh_bytes, long vertices, size_t gbuffer_pixel,
                                 int lobe_sets, int cube_maps, int sun_maps, int sky_maps)
{
    sl_lighting_options modes = sl_lighting_options_resolve(&d->lighting);
    memory_model m = {.program = PROGRAM_BYTES};
    if (env_w <= 0)
        env_w = env_h = 1;
    size_t P = (size_t)env_w * (size_t)env_h;
    m.env_load = env_file + P * 12;
    m.env_build = P * 12 + env_build_bytes(env_w, env_h);
    m.env = chain_held_bytes(env_w, env_h, true);
    size_t base = m.program + mesh_bytes;
    phase(&m, base + m.env_load, "reading the environment");
    phase(&m, base + m.env_build, "building the environment's mip chain");
    base += m.env;
    if (!d->lighting.no_diffuse) {
        if (d->lighting.irradiance == SL_IRRADIANCE_MAP && irr_w > 0) {
            size_t Pi = (size_t)irr_w * (size_t)irr_h;
            m.irradiance = Pi * 12;
            m.irradiance_build = (irr_file + Pi * 12 > Pi * 24 ? irr_file + Pi * 12 : Pi * 24);
        } else if (d->lighting.irradiance == SL_IRRADIANCE_BRUTE) {
            int w = env_w, h = env_h; /* the finest level with at most SL_IRRADIANCE_BRUTE_TEXELS texels */
            while ((long)w * h > SL_IRRADIANCE_BRUTE_TEXELS && (w > 1 || h > 1)) {
                w = w / 2 > 1 ? w / 2 : 1;
                h = h / 2 > 1 ? h / 2 : 1;
            }
            int mw = d->irradiance_map_width ? d->irradiance_map_width : 64;
            m.irradiance = (size_t)mw * (size_t)(mw / 2 > 1 ? mw / 2 : 1) * 12;
            m.irradiance_build = (size_t)w * (size_t)h * 48 + m.irradiance;
        } else {
            m.irradiance_build = (size_t)env_w * 40; /* SH9: one row of column moments */
        }
        phase(&m, base + m.irradiance_build, "computing the irradiance");
        base += m.irradiance;
    }
    if (d->lighting.env_lights > 0) {
        m.env_lights = m.env;
        size_t extract = P * 48 + P * 12, residual = P * 12 + env_build_bytes(env_w, env_h);
        m.env_lights_build = extract > residual ? extract : residual;
        phase(&m, base + m.env_lights_build, "extracting the env lights");
        base += m.env_lights;
    }
    if (modes.env_layout == SL_ENV_LAYOUT_OCT) {
        size_t texels = oct_chain_texels(env_w);
        m.env_oct = texels * 12;
        m.env_oct_build = texels * 16;
        phase(&m, base + m.env_oct_build, "building the octahedral chain");
        base += m.env_oct;
    }
    if (sl_estimator_reads_splitsum(modes.estimator) || sl_estimator_reads_splitsum(modes.ggx.estimator)) {
        m.splitsum = (size_t)lobe_sets * chain_held_bytes(env_w, env_h, false) + sizeof(sl_splitsum_lut);
        phase(&m, base + m.splitsum, "prefiltering for the split sum");
        base += m.splitsum;
    }
    if (sl_estimator_reads_env_dist(modes.estimator) || sl_estimator_reads_env_dist(modes.ggx.estimator)) {
        int gw = env_w, gh = env_h; /* the grid: halved while wider than SL_ENV_DIST_MAX_WIDTH */
        while (gw > SL_ENV_DIST_MAX_WIDTH && gw % 2 == 0 && gh % 2 == 0) {
            gw /= 2;
            gh /= 2;
        }
        m.env_dist = (size_t)gw * (size_t)gh * 8 + (size_t)gh * 4 + (P <= SL_ENV_PAIRS_MAX_TEXELS ? P * 16 : 0);
        phase(&m, base + m.env_dist, "building the environment distribution");
        base += m.env_dist;
    }
    /* G-buffer 56 B (76 with the extra plane: gbuffer.h), radiance and display images 12 B each, the PNG's 8-bit pixels, its filtered
     * rows and its growing zlib buffer (about 15 B together), per pixel; the rasterizer's copy of
     * the transformed vertices (rast_vpos and varyings, about 80 B each). */
    size_t pixels = (size_t)d->width * (size_t)d->height;
    m.frame = pixels * (gbuffer_pixel + 12 + 12 + 15) + (size_t)vertices * 80;
    /* the shadow maps are drawn after the G-buffer, before the lighting (renderer.c) */
    size_t face = (size_t)(SL_SHADOW_CUBE_SIZE + 2 * SL_SHADOW_GUARD) * (size_t)(SL_SHADOW_CUBE_SIZE + 2 * SL_SHADOW_GUARD);
    size_t sun = (size_t)SL_SHADOW_SUN_SIZE * (size_t)SL_SHADOW_SUN_SIZE;
    size_t sky = (size_t)SL_SKY_MAP_SIZE * (size_t)SL_SKY_MAP_SIZE;
    m.shadows = (size_t)cube_maps * 6 * face * 4 + (size_t)sun_maps * sun * 4 + (size_t)sky_maps * sky * 4;
    m.shadows_build = sun_maps > 0 ? sun * 8 : sky_maps > 0 ? sky * 8 : cube_maps > 0 ? face * 8 : 0;
    if (m.shadows > 0)
        phase(&m, base + m.frame + m.shadows + m.shadows_build, "drawing the shadow maps");
    phase(&m, base + m.shadows + m.frame, "rendering and writing the frame");
    return m;
}

static size_t file_bytes(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode) ? (size_t)st.st_size : 0;
}

static void print_vec3(const char *label, vec3 v)
{
    printf("  %-10s (%g, %g, %g)\n", label, (double)v.x, (double)v.y, (double)v.z);
}

int cmd_info(int argc, char **argv)
{
    sl_render_options ro;
    sl_arg table[SL_RENDER_OPTION_COUNT];
    const int n = sl_render_options_table(&ro, table);
    const char *positional[1];
    int npos;
    bool help;
    sl_error err = {0};
    if (!sl_args_parse(argc, argv, 2, table, n, positional, 1, &npos, &help, &err)) {
        fprintf(stderr, "softlight info: %s\n", err.msg);
        return 2;
    }
    if (help || npos != 1) {
        sl_args_print_help(help ? stdout : stderr,
                           "softlight info SCENE.json [render options: the peak memory is that render's]", table,
                           n);
        return help ? 0 : 2;
    }
    sl_render_desc desc;
    if (!sl_render_options_desc(&ro, &desc, &err)) {
        fprintf(stderr, "softlight info: %s\n", err.msg);
        return 2;
    }
    sl_scene scene;
    if (!sl_scene_load_with(positional[0], &desc.options, &scene, &err)) {
        fprintf(stderr, "softlight info: %s\n", err.msg);
        return 2;
    }
    fputs(scene.warnings, stderr); /* what the scene loads but does not draw */

    long vertices = 0, triangles = 0;
    size_t mesh_bytes = 0;
    for (int i = 0; i < scene.mesh_count; i++) {
        const sl_mesh *m = &scene.meshes[i];
        mesh_bytes += (size_t)m->vertex_count * (2 * sizeof(vec3) + (m->texcoords ? sizeof(vec2) + sizeof(vec4) : 0)) +
                      (size_t)m->triangle_count * 3 * sizeof(uint32_t);
    }
    for (int i = 0; i < scene.object_count; i++) {
        const sl_mesh *m = &scene.meshes[scene.objects[i].mesh];
        vertices += m->vertex_count;
        triangles += m->triangle_count;
    }

    printf("scene %s\n", scene.path);
    printf("  objects    %d (%ld triangles, %ld vertices drawn; %d distinct meshes)\n", scene.object_count,
           triangles, vertices, scene.mesh_count);
    for (int i = 0; i < scene.object_count; i++) {
        const sl_object *o = &scene.objects[i];
        const sl_material *mat = &scene.materials[o->material];
        printf("    [%d] %-12s %7d triangles  material %s (kd %.3g %.3g %.3g, ks %.3g %.3g %.3g, alpha %g)\n", i,
               o->name, scene.meshes[o->mesh].triangle_count, mat->name, (double)mat->kd.x, (double)mat->kd.y,
               (double)mat->kd.z, (double)mat->ks.x, (double)mat->ks.y, (double)mat->ks.z, (double)mat->alpha);
    }
    printf("  materials  %d\n", scene.material_count);
    printf("  lights     %d point light%s\n", scene.light_count, scene.light_count == 1 ? "" : "s");
    vec3 lo, hi;
    if (sl_scene_bounds(&scene, &lo, &hi)) {
        print_vec3("bounds min", lo);
        print_vec3("bounds max", hi);
    }
    const sl_camera *c = &scene.camera;
    print_vec3("eye", c->eye);
    print_vec3("target", c->target);
    printf("  fovy       %g degrees, near %g, far %g\n", (double)c->fovy_deg, (double)c->znear, (double)c->zfar);

    if (!sl_render_desc_resolve(&desc, &scene, &err)) { /* what `render` with these options uses */
        fprintf(stderr, "softlight info: %s\n", err.msg);
        sl_scene_free(&scene);
        return 2;
    }
    const sl_option_values *s = &desc.options; /* the scene's, the command line's over them, the defaults */
    printf("  render     %dx%d, N = %d samples, exposure %g, contrast %g\n", s->size[0], s->size[1], s->samples,
           (double)s->exposure, (double)s->contrast);
    const sl_lighting_options modes = desc.lighting;
    char env_lights[128] = "";
    if (modes.env_lights > 0)
        snprintf(env_lights, sizeof env_lights,
                 modes.env_lights_worth ? ", env lights up to %d (those worth their cost)%s" : ", env lights %d%s",
                 modes.env_lights, modes.env_lights_ggx_only ? ", the GGX materials' alone" : "");
    printf("  lighting   estimator %s, lod %s, g %s, env layout %s, irradiance %s%s%s%s (with these options)\n",
           sl_estimator_name(modes.estimator), sl_lod_rule_name(modes.lod_rule), sl_gterm_name(modes.gterm),
           sl_env_layout_name(modes.env_layout), sl_irradiance_name(modes.irradiance),
           modes.distortion ? ", distortion" : "", modes.rotate ? ", rotate" : "", env_lights);
    if (modes.ggx.estimator != SL_ESTIMATOR_DEFAULT)
        printf("  GGX        estimator %s, lod %s%s (the GGX materials'; the line above is the Phong materials')\n",
               sl_estimator_name(modes.ggx.estimator), sl_lod_rule_name(modes.ggx.lod_rule),
               modes.ggx.distortion ? ", distortion" : "");

    /* Both images are read as `render` reads them (the same checks, the same memory budget). */
    int env_w = 0, env_h = 0, irr_w = 0, irr_h = 0;
    const sl_environment_desc *e = &scene.environment;
    if (e->hdr_path[0]) {
        sl_image env;
        if (!sl_image_read_radiance(e->hdr_path, desc.image_budget, &env, NULL, &err)) {
            fprintf(stderr, "softlight info: %s\n", err.msg);
            sl_scene_free(&scene);
            return 2;
        }
        env_w = env.width;
        env_h = env.height;
        sl_image_free(&env);
        printf("  environment %s: %dx%d, intensity %g, rotation %g degrees%s%s\n", e->hdr_path, env_w, env_h,
               (double)s->env_intensity, (double)e->rotation_deg, e->irradiance_path[0] ? ", irradiance " : "",
               e->irradiance_path);
    } else {
        printf("  environment none (black)\n");
    }
    if (e->irradiance_path[0] && desc.lighting.irradiance == SL_IRRADIANCE_MAP && !desc.lighting.no_diffuse) {
        sl_image map;
        if (!sl_image_read_radiance(e->irradiance_path, desc.image_budget, &map, NULL, &err)) {
            fprintf(stderr, "softlight info: %s\n", err.msg);
            sl_scene_free(&scene);
            return 2;
        }
        irr_w = map.width;
        irr_h = map.height;
        sl_image_free(&map);
    }

    /* the G-buffer's extra plane only when a drawn material writes it (sl_raster_scene_textured's rule)
     * or ambient occlusion does; the occlusion pass's own buffers, two 16-byte planes on the
     * half-resolution grid (samples, tangent planes), and the 16-byte cone plane at full
     * resolution, count with each pixel (24 bytes); the reflection occlusion's 4-byte plane and
     * the 12-byte facet plane it asks the rasterizer for (its pass's 24 bytes of scratch a pixel
     * are freed before the lighting's buffers, which make the peak, are allocated: measured on
     * bunny.json at 1280x720, 4 MiB more resident at the peak) */
    bool extra = desc.options.ao_radius > 0.0f;
    for (int i = 0; i < scene.object_count; i++)
        extra |= sl_material_extra(&scene.materials[scene.objects[i].material]);
    size_t gbuffer_pixel = sl_gbuffer_pixel_bytes(extra) + (desc.options.ao_radius > 0.0f ? 24 : 0) +
                           (desc.options.reflection_occlusion > 0.0f ? 4 + sizeof(sl_vec3) : 0);
    bool phong, ggx; /* the split sum's lobe sets */
    sl_renderer_splitsum_sets(&scene, &phong, &ggx);
    /* the shadow maps: a cube per light that casts; a map per cluster of env lights, at most
     * SL_SHADOW_SUN_MAX (the clusters need the lights, which info does not extract: the most) */
    int cube_maps = 0, sun_maps = 0;
    for (int i = 0; i < scene.light_count; i++)
        cube_maps += desc.options.shadows || scene.lights[i].shadow;
    if (desc.options.shadows && desc.lighting.env_lights > 0)
        sun_maps = desc.lighting.env_lights < SL_SHADOW_SUN_MAX ? desc.lighting.env_lights : SL_SHADOW_SUN_MAX;
    memory_model m = model_render(&desc, env_w, env_h, e->hdr_path[0] ? file_bytes(e->hdr_path) : 0, irr_w, irr_h,
                                  irr_w ? file_bytes(e->irradiance_path) : 0, mesh_bytes, vertices, gbuffer_pixel,
                                  (int)phong + (int)ggx, cube_maps, sun_maps, desc.options.sky_maps);
    double mib = 1024.0 * 1024.0;
    printf("  memory     peak %.1f MiB while %s (a %dx%d render%s%s)\n", (double)m.peak / mib, m.peak_at,
           desc.width, desc.height, desc.lighting.env_lights ? " with env lights" : "",
           desc.lighting.irradiance == SL_IRRADIANCE_MAP && irr_w ? ", irradiance map" : "");
    printf("             environment %.1f MiB held (mip chain), %.1f MiB while read, %.1f MiB while its mips are "
           "built; irradiance %.1f MiB held, %.1f MiB while built; env lights %.1f MiB held, %.1f MiB while "
           "extracted; octahedral chain %.1f MiB held; split-sum chains %.1f MiB held; environment distribution "
           "%.1f MiB held; shadow maps %.1f MiB held (%d cube%s, %s%d env-light map%s, %d sky map%s), %.1f MiB while "
           "drawn; "
           "frame %.1f MiB (G-buffer %zu B/pixel%s); meshes %.1f MiB; program %.1f MiB\n",
           (double)m.env / mib, (double)m.env_load / mib, (double)m.env_build / mib, (double)m.irradiance / mib,
           (double)m.irradiance_build / mib, (double)m.env_lights / mib, (double)m.env_lights_build / mib,
           (double)m.env_oct / mib, (double)m.splitsum / mib, (double)m.env_dist / mib, (double)m.shadows / mib,
           cube_maps, cube_maps == 1 ? "" : "s", sun_maps ? "at most " : "", sun_maps, sun_maps == 1 ? "" : "s",
           desc.options.sky_maps, desc.options.sky_maps == 1 ? "" : "s",
           (double)m.shadows_build / mib, (double)m.frame / mib, gbuffer_pixel, extra ? " with occlusion and emission" : "", (double)mesh_bytes / mib,
           (double)m.program / mib);
    sl_scene_free(&scene);
    return 0;
}
