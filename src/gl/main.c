/* main.c - the softlight-gl command line: `softlight-gl render scene.json [options]`.
 *
 * The same frame as `softlight render`, with OpenGL doing the two stages softlight does in C
 * (rasterization into the G-buffer, lighting), and softlight's C code doing everything else, so
 * that the two programs' files can be diffed with `softlight compare`. Options are those of
 * `softlight render` where they apply, plus:
 *   --gbuffer DIR  skip the G-buffer pass and light softlight's G-buffer (its --aov files), which
 *                  tells a rasterization difference from a shading one;
 *   --gbuffer-shader FILE.frag  draw every object with this fragment shader behind
 *                  gbuffer_textured.vert (the GLSL twin of softlight's --gbuffer-shader FILE.c);
 *   --time N       run each pass N times and print the median milliseconds per stage, timed with
 *                  glFinish and a monotonic clock (no timer queries: llvmpipe's are not meaningful);
 *   --verbose      print GL_RENDERER and what was done.
 * `softlight-gl info` prints the renderer and exits 0, or says in one line why there is no GL
 * and exits 2 (what the tests use to decide whether GL can run here).
 * Exit status: 0 success, 2 any error (one line on stderr). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/args.h"
#include "app/render_options.h"
#include "render/renderer.h"
#include "core/output_set.h"
#include "core/timer.h"
#include "post/tonemap.h"
#include "scene/camera.h"
#include "slgl.h"
#include "softlight/version.h"

#define TIME_MAX_RUNS 1000

typedef struct {
    const char *scene_path;
    const char *png, *hdr, *pfm, *aov_dir, *gbuffer_dir;
    const char *lighting; /* --lighting my.frag: the user's GLSL lighting shader */
    const char *gbuffer_shader; /* --gbuffer-shader: the user's G-buffer fragment shader, or NULL */
    int time_runs;
    bool verbose;
    /* --eye, --target, --up, --fovy, --env-rotation: the scene's camera and environment rotation
     * replaced, for a G-buffer drawn from elsewhere (softlight view's GL comparison) */
    sl_camera camera;
    float env_rotation_deg;
    unsigned given; /* GIVEN_* bits */
} gl_outputs;

enum { GIVEN_EYE = 1u, GIVEN_TARGET = 2u, GIVEN_UP = 4u, GIVEN_FOVY = 8u, GIVEN_ENV_ROTATION = 16u };

/* Everything a frame needs that is built on the CPU. sl_renderer is softlight's own frame state:
 * it resolves the options against the scene, loads the environment, builds its mip chain and
 * irradiance and derives the lighting uniforms exactly as `softlight render` does; softlight-gl
 * then uses its numbers and skips its raster and shading stages. */
typedef struct {
    sl_scene scene;
    bool scene_loaded;
    sl_renderer renderer;
    bool renderer_ready;
    mat4 view_proj;
    int width, height;
} frame;

static double median_ms(double *seconds, int n) { return 1000.0 * sl_median(seconds, n); }

static void frame_free(frame *f)
{
    if (f->renderer_ready)
        sl_renderer_free(&f->renderer);
    if (f->scene_loaded)
        sl_scene_free(&f->scene);
    memset(f, 0, sizeof *f);
}

/* The scene's camera and environment rotation, with what the command line gave in their place. */
static bool frame_override(frame *f, const gl_outputs *o, sl_error *err)
{
    sl_camera *c = &f->scene.camera;
    if (o->given & GIVEN_EYE)
        c->eye = o->camera.eye;
    if (o->given & GIVEN_TARGET)
        c->target = o->camera.target;
    if (o->given & GIVEN_UP)
        c->up = o->camera.up;
    if (o->given & GIVEN_FOVY)
        c->fovy_deg = o->camera.fovy_deg;
    if (o->given & GIVEN_ENV_ROTATION)
        f->scene.environment.rotation_deg = o->env_rotation_deg;
    if (!(o->given & (GIVEN_EYE | GIVEN_TARGET | GIVEN_UP)))
        return true;
    /* the scene reader's checks of its camera, for the one the command line made */
    vec3 forward = sub3(c->target, c->eye);
    float forward_len = length3(forward), up_len = length3(c->up);
    if (!(forward_len > 0.0f))
        return sl_fail(err, SL_ERR_RANGE, "--eye, --target: the camera's eye and target coincide");
    if (!(length3(cross(forward, c->up)) > 1e-4f * forward_len * up_len))
        return sl_fail(err, SL_ERR_RANGE, "--up: zero or parallel to the view direction (target - eye)");
    return true;
}

static bool frame_build(frame *f, const gl_outputs *o, const sl_render_desc *desc, sl_error *err)
{
    memset(f, 0, sizeof *f);
    if (!sl_scene_load_with(o->scene_path, &desc->options, &f->scene, err))
        return false;
    fputs(f->scene.warnings, stderr); /* what the scene loads but does not draw */
    f->scene_loaded = true;
    if (!frame_override(f, o, err))
        return false;
    if (!sl_renderer_init(&f->renderer, &f->scene, desc, err))
        return false;
    f->renderer_ready = true;
    f->width = f->renderer.gbuffer.width;
    f->height = f->renderer.gbuffer.height;
    f->view_proj = sl_camera_view_proj(&f->scene.camera, f->width, f->height);
    return sl_renderer_prepare_lighting(&f->renderer, NULL, err);
}

/* The images, added to the command's output set (committed with the AOVs by render). */
static bool add_outputs(const gl_outputs *o, const frame *f, const sl_image *radiance, sl_output_set *out,
                        sl_error *err)
{
    if (o->png) {
        sl_image ldr = {0};
        bool ok = sl_tonemap_image(radiance, &ldr, &f->renderer.desc.tonemap, f->renderer.desc.threads, err) &&
                  sl_output_set_image(out, o->png, sl_image_encode_png, &ldr, err);
        sl_image_free(&ldr);
        if (!ok)
            return false;
    }
    if (o->hdr && !sl_output_set_image(out, o->hdr, sl_image_encode_hdr, radiance, err))
        return false;
    return !o->pfm || sl_output_set_image(out, o->pfm, sl_image_encode_pfm, radiance, err);
}

/* Which microfacet sets the lit pixels use, for the lighting program's specialization: those of
 * the drawn objects' materials, or, with --gbuffer, of the covered texels (alpha <= -1 is GGX,
 * src/raster/gbuffer.h; lighting.frag's lobe_param keeps that sign). */
static void lobes_used(const sl_scene *scene, const sl_gbuffer *files, bool *phong, bool *ggx)
{
    *phong = *ggx = false;
    if (files) {
        size_t n = (size_t)files->width * (size_t)files->height;
        for (size_t i = 0; i < n; i++)
            if (sl_gbuffer_covered(&files->texels[i])) {
                bool is_ggx = files->texels[i].alpha <= -1.0f;
                *ggx |= is_ggx;
                *phong |= !is_ggx;
            }
        return;
    }
    for (int i = 0; i < scene->object_count; i++) {
        bool is_ggx = scene->materials[scene->objects[i].material].brdf == SL_BRDF_GGX;
        *ggx |= is_ggx;
        *phong |= !is_ggx;
    }
}

/* The G-buffer and lighting passes, `runs` times each (1 normally), with per-stage medians.
 * `files` is softlight's G-buffer read from --gbuffer DIR (NULL without it). */
static bool render(const gl_outputs *o, frame *f, const sl_gbuffer *files, sl_error *err)
{
    slgl_gbuffer g = {0};
    slgl_lighting l = {0};
    slgl_occlusion occlusion = {0};
    slgl_textures textures = {0};
    slgl_shadows shadow_maps = {0};
    slgl_shadows_destroy(&shadow_maps); /* empty: no light casts */
    slgl_mesh *meshes = calloc((size_t)(f->scene.mesh_count > 0 ? f->scene.mesh_count : 1), sizeof *meshes);
    sl_gbuffer gb = {0};
    sl_image radiance = {0};
    sl_output_set out = {0};
    int runs = o->time_runs > 0 ? o->time_runs : 1;
    double *t_gbuffer = calloc((size_t)runs, sizeof(double)), *t_lighting = calloc((size_t)runs, sizeof(double));
    bool ok = false;
    if (!meshes || !t_gbuffer || !t_lighting) {
        sl_fail(err, SL_ERR_MEMORY, "no memory");
        goto done;
    }
    /* the lights' shadow maps, drawn by GL from the meshes (with --gbuffer too): the point
     * lights', and with --shadows the env lights' (those softlight's renderer extracted) */
    bool shadows_all = f->renderer.desc.options.shadows;
    const sl_env_lights *env_lights =
        shadows_all && f->renderer.desc.lighting.env_lights > 0 && f->renderer.env_lights_built > 0
            ? &f->renderer.env_lights
            : NULL;
    /* the sky visibility maps (--sky-maps K, the scene's render.sky_maps), weighted by what
     * softlight's renderer weighted its own with: the env lights' residual when their maps take
     * them out of the irradiance, else the environment (src/render/renderer.c update_sky) */
    int sky_maps = f->renderer.desc.options.sky_maps;
    const sl_env *sky_env = f->renderer.sky_env_lights > 0 ? &f->renderer.env_lights.residual : &f->renderer.env;
    bool shadows = sl_shadow_any(&f->scene, shadows_all) || env_lights || sky_maps > 0;
    /* ambient occlusion after the G-buffer pass (shaders/gtao*.frag); softlight's G-buffer files
     * (--gbuffer) carry it already in their occlusion */
    float ao_radius = o->gbuffer_dir ? 0.0f : f->renderer.desc.options.ao_radius;
    /* the extra target only where softlight allocates its extra plane (src/raster/gbuffer.h) */
    bool extra = false;
    for (int i = 0; i < f->scene.object_count; i++)
        extra |= sl_material_extra(&f->scene.materials[f->scene.objects[i].material]);
    extra |= ao_radius > 0.0f;
    if (o->gbuffer_dir)
        extra = files->extra != NULL;
    if (!slgl_gbuffer_create(&g, f->width, f->height, extra, err) ||
        (o->gbuffer_shader && !slgl_gbuffer_use_fragment(&g, o->gbuffer_shader, err)) ||
        !slgl_lighting_create(&l, f->width, f->height, err) ||
        (ao_radius > 0.0f && !slgl_occlusion_create(&occlusion, f->width, f->height, err)))
        goto done;
    l.user_frag = o->lighting;
    if (!slgl_lighting_set_environment(&l, &f->renderer.env,
                                       f->renderer.env_oct_built >= 0     ? &f->renderer.env_oct
                                       : f->renderer.env_lights_built > 0 ? &f->renderer.env_lights.residual
                                                                          : NULL,
                                       f->renderer.have_irradiance ? &f->renderer.irradiance : NULL, err) ||
        !slgl_lighting_set_splitsum(&l, sl_renderer_splitsum_chain(&f->renderer, false),
                                    sl_renderer_splitsum_chain(&f->renderer, true), f->renderer.splitsum_lut, err))
        goto done;
    bool phong, ggx;
    lobes_used(&f->scene, files, &phong, &ggx);
    slgl_lighting_set_lobes(&l, phong || o->gbuffer_shader, ggx || o->gbuffer_shader); /* a user's: either */
    if (o->gbuffer_dir && !slgl_gbuffer_upload(&g, files, err))
        goto done;
    /* the G-buffer pass's maps, and the masked casters' masks the shadow maps read */
    if ((!o->gbuffer_dir || shadows) && !slgl_textures_upload(&f->renderer.textures, &textures, err))
        goto done;
    if ((!o->gbuffer_dir || shadows) && !slgl_meshes_upload(&f->scene, meshes, err))
        goto done;
    /* the maps depend on the scene alone: drawn once, before the timed passes */
    double t_shadows = sl_now_seconds();
    if (shadows && !slgl_shadows_draw(&shadow_maps, &f->scene, meshes, &f->renderer.textures, &textures, shadows_all,
                                      env_lights, f->renderer.desc.lighting.env_rotation_deg, sky_maps, sky_env, err))
        goto done;
    glFinish();
    t_shadows = sl_now_seconds() - t_shadows;
    int suns = shadow_maps.sun_frames.count;
    if (shadows && o->verbose && suns == 0)
        printf("shadow maps: %d cube map%s of %d texels a face side, drawn in %.1f ms (glFinish)\n",
               shadow_maps.cube_count, shadow_maps.cube_count == 1 ? "" : "s", SL_SHADOW_CUBE_SIZE, t_shadows * 1e3);
    else if (shadows && o->verbose)
        printf("shadow maps: %d cube map%s of %d texels a face side, %d env-light map%s of %d texels a side, drawn "
               "in %.1f ms (glFinish)\n",
               shadow_maps.cube_count, shadow_maps.cube_count == 1 ? "" : "s", SL_SHADOW_CUBE_SIZE, suns,
               suns == 1 ? "" : "s", SL_SHADOW_SUN_SIZE, t_shadows * 1e3);
    if (sky_maps > 0 && o->verbose)
        printf("sky visibility maps: %d of %d texels a side, weighted by %s\n", shadow_maps.sky_frames.count,
               SL_SKY_MAP_SIZE, f->renderer.sky_env_lights > 0 ? "the env lights' residual" : "the environment");
    slgl_lighting_set_shadows(&l, &shadow_maps);
    glFinish();
    for (int run = 0; run < runs; run++) {
        double t0 = sl_now_seconds();
        if (!o->gbuffer_dir && !slgl_gbuffer_draw(&g, &f->scene, meshes, &f->renderer.textures, &textures,
                                                    f->view_proj, err))
            goto done;
        if (ao_radius > 0.0f && !slgl_occlusion_draw(&occlusion, &g, &f->scene.camera, ao_radius, err))
            goto done;
        glFinish();
        double t1 = sl_now_seconds();
        if (!slgl_lighting_draw(&l, &g, f->renderer.uniforms, err))
            goto done;
        glFinish();
        double t2 = sl_now_seconds();
        t_gbuffer[run] = t1 - t0;
        t_lighting[run] = t2 - t1;
    }
    long repaired = 0;
    if (!slgl_lighting_read(&l, &radiance, &repaired, err))
        goto done;
    /* Every output into one set: replaced together once all were written, or none of them. */
    if (!add_outputs(o, f, &radiance, &out, err))
        goto done;
    if (o->aov_dir) {
        if (!o->gbuffer_dir && !slgl_gbuffer_read(&g, &gb, err))
            goto done;
        if (!sl_output_set_dir(&out, o->aov_dir, err) ||
            !sl_gbuffer_add_aovs(o->gbuffer_dir ? files : &gb, f->scene.camera.eye, o->aov_dir, &out, err))
            goto done;
    }
    if (!sl_output_set_commit(&out, err))
        goto done;
    if (repaired && o->lighting)
        fprintf(stderr, "softlight-gl: warning: %s: %ld pixels had NaN/Inf radiance (written as magenta)\n",
                o->lighting, repaired);
    else if (repaired)
        fprintf(stderr, "softlight-gl: warning: lighting.frag repaired %ld non-finite pixels (written as 0)\n",
                repaired);
    if (o->time_runs > 0)
        printf("time: %d runs, %dx%d, %d samples: gbuffer %.3f ms%s, lighting %.3f ms (median, glFinish)\n", runs,
               f->width, f->height, f->renderer.desc.lighting.samples, median_ms(t_gbuffer, runs),
               o->gbuffer_dir ? " (skipped: --gbuffer)" : "", median_ms(t_lighting, runs));
    ok = true;
done:
    sl_output_set_free(&out);
    sl_image_free(&radiance);
    sl_gbuffer_free(&gb);
    if (meshes)
        slgl_meshes_destroy(meshes, f->scene.mesh_count);
    free(meshes);
    slgl_textures_destroy(&textures);
    slgl_lighting_destroy(&l);
    slgl_shadows_destroy(&shadow_maps);
    if (occlusion.program)
        slgl_occlusion_destroy(&occlusion);
    slgl_gbuffer_destroy(&g);
    free(t_gbuffer);
    free(t_lighting);
    return ok;
}

#define OUTPUT_OPTION_COUNT 14

static int cmd_render(int argc, char **argv)
{
    gl_outputs o = {0};
    sl_render_options ro;
    sl_arg table[SL_RENDER_OPTION_COUNT + OUTPUT_OPTION_COUNT];
    const int n = sl_render_options_table(&ro, table);
    const sl_arg outputs[OUTPUT_OPTION_COUNT] = {
        {"--output", "-o", SL_ARG_STRING, &o.png, 0, 0, NULL, "OUT.png", "tone-mapped 8-bit image", NULL},
        {"--hdr", NULL, SL_ARG_STRING, &o.hdr, 0, 0, NULL, "OUT.hdr", "linear radiance, Radiance RGBE", NULL},
        {"--pfm", NULL, SL_ARG_STRING, &o.pfm, 0, 0, NULL, "OUT.pfm", "linear radiance, float", NULL},
        {"--aov", NULL, SL_ARG_STRING, &o.aov_dir, 0, 0, NULL, "DIR", "write GL's G-buffer as softlight's AOV files",
         NULL},
        {"--gbuffer", NULL, SL_ARG_STRING, &o.gbuffer_dir, 0, 0, NULL, "DIR",
         "light softlight's G-buffer (its --aov files) instead of rasterizing", NULL},
        {"--gbuffer-shader", NULL, SL_ARG_STRING, &o.gbuffer_shader, 0, 0, NULL, "FILE.frag",
         "draw every object with this G-buffer fragment shader (docs/gbuffer-programs.md)", NULL},
        {"--time", NULL, SL_ARG_INT, &o.time_runs, 1, TIME_MAX_RUNS, NULL, "N", "run each pass N times, print medians",
         NULL},
        {"--verbose", "-v", SL_ARG_FLAG, &o.verbose, 0, 0, NULL, NULL, "print the GL renderer and what was done",
         NULL},
        {"--lighting", NULL, SL_ARG_STRING, &o.lighting, 0, 0, NULL, "FILE.frag",
         "light with this GLSL shader, compiled after lighting.frag (docs/lighting-programs.md)", NULL},
        {"--eye", NULL, SL_ARG_VEC3, &o.camera.eye, -1e30, 1e30, NULL, "X,Y,Z",
         "the camera's position (default: the scene's)", &(const sl_arg_mark){&o.given, GIVEN_EYE}},
        {"--target", NULL, SL_ARG_VEC3, &o.camera.target, -1e30, 1e30, NULL, "X,Y,Z",
         "the point the camera looks at (default: the scene's)", &(const sl_arg_mark){&o.given, GIVEN_TARGET}},
        {"--up", NULL, SL_ARG_VEC3, &o.camera.up, -1e30, 1e30, NULL, "X,Y,Z", "the camera's up (default: the scene's)",
         &(const sl_arg_mark){&o.given, GIVEN_UP}},
        {"--fovy", NULL, SL_ARG_FLOAT, &o.camera.fovy_deg, 0.01, 179.0, NULL, "DEG",
         "vertical field of view (default: the scene's)", &(const sl_arg_mark){&o.given, GIVEN_FOVY}},
        {"--env-rotation", NULL, SL_ARG_FLOAT, &o.env_rotation_deg, -1e6, 1e6, NULL, "DEG",
         "the environment's rotation about +Z (default: the scene's)",
         &(const sl_arg_mark){&o.given, GIVEN_ENV_ROTATION}},
    };
    memcpy(table + n, outputs, sizeof outputs);
    const int count = n + OUTPUT_OPTION_COUNT;
    const char *usage = "softlight-gl render SCENE.json [options]";
    const char *positional[1];
    int npos = 0;
    bool help = false;
    sl_error err = {0};
    sl_render_desc desc;
    if (!sl_args_parse(argc, argv, 2, table, count, positional, 1, &npos, &help, &err) ||
        (!help && !sl_render_options_desc(&ro, &desc, &err))) {
        fprintf(stderr, "softlight-gl render: %s\n", err.msg);
        return 2;
    }
    if (help) {
        sl_args_print_help(stdout, usage, table, count);
        printf("\n--threads and --tile set softlight's CPU stages, which softlight-gl does not run.\n");
        return 0;
    }
    if (npos != 1) {
        fprintf(stderr, "softlight-gl render: expected one scene file (see --help)\n");
        return 2;
    }
    o.scene_path = positional[0];
    desc.any_lobe = o.gbuffer_shader != NULL;
    if (o.gbuffer_shader && o.gbuffer_dir) {
        fprintf(stderr, "softlight-gl render: --gbuffer-shader draws a G-buffer, --gbuffer reads one: not both\n");
        return 2;
    }

    slgl_context ctx;
    if (!slgl_context_create(&ctx, &err)) {
        fprintf(stderr, "softlight-gl: %s\n", err.msg);
        return 2;
    }
    if (o.verbose)
        printf("GL_RENDERER: %s\nGL_VERSION: %s\n", ctx.renderer, ctx.version);
    /* softlight's G-buffer files set the frame size unless --size does. */
    sl_gbuffer files = {0};
    if (o.gbuffer_dir) {
        if (!sl_gbuffer_read_aovs(o.gbuffer_dir, &files, &err)) {
            fprintf(stderr, "softlight-gl: --gbuffer: %s\n", err.msg);
            slgl_context_destroy(&ctx);
            return 2;
        }
        if (!sl_option_is_set(&desc.options, SL_OPT_SIZE))
            sl_option_set_size(&desc.options, files.width, files.height);
    }
    frame f;
    bool ok = frame_build(&f, &o, &desc, &err) && render(&o, &f, o.gbuffer_dir ? &files : NULL, &err);
    if (ok && o.verbose)
        printf("rendered %s: %dx%d, %d samples%s\n", o.scene_path, f.width, f.height,
               f.renderer.desc.lighting.samples, o.gbuffer_dir ? " (G-buffer from files)" : "");
    frame_free(&f);
    sl_gbuffer_free(&files);
    slgl_context_destroy(&ctx);
    if (!ok) {
        fprintf(stderr, "softlight-gl: %s\n", err.msg);
        return 2;
    }
    return 0;
}

static int cmd_info(void)
{
    slgl_context ctx;
    sl_error err = {0};
    if (!slgl_context_create(&ctx, &err)) {
        fprintf(stderr, "softlight-gl: %s\n", err.msg);
        return 2;
    }
    printf("GL_RENDERER: %s\nGL_VERSION: %s\nshaders: %s\n", ctx.renderer, ctx.version, slgl_shader_dir());
    slgl_context_destroy(&ctx);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        printf("usage: softlight-gl render SCENE.json [options]   (render --help for the options)\n"
               "       softlight-gl info                         (the OpenGL renderer, or why there is none)\n"
               "       softlight-gl --version\n");
        return argc < 2 ? 2 : 0;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("softlight %s\n", SL_VERSION_STRING);
        return 0;
    }
    if (!strcmp(argv[1], "render"))
        return cmd_render(argc, argv);
    if (!strcmp(argv[1], "info"))
        return cmd_info();
    fprintf(stderr, "softlight-gl: unknown command '%s' (render, info)\n", argv[1]);
    return 2;
}
