/* gbuffer_program.c - your own G-buffer program feeding softlight's deferred lighting.
 *
 * A C fragment program writes the G-buffer texel (world position, normal, diffuse and specular
 * colour, lobe, depth) with a procedural material: a checker of gold and glazed blue whose
 * edges are filtered with fwidth(). softlight's renderer then lights that G-buffer with the
 * image-based lighting of a scene's environment (sl_renderer_light) and tone maps it.
 *
 *   gbuffer_program OUT.png [WIDTHxHEIGHT] [SCENE.json]
 *
 * The scene (default: softlight's scenes/default.json, the studio environment) gives only the
 * environment, its lights and the tone map; the geometry and the materials are this file's. */
#include <math.h>
#include <stdio.h>

#include <softlight/glsl.h>
#include <softlight/softlight.h>

typedef struct { mat4 model, view_proj; mat3 normal_matrix; } vs_uniforms;
typedef struct { float cells; vec3 kd[2], ks[2]; float roughness[2]; } fs_uniforms;

static void vertex(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    const vs_uniforms *u = uniforms;
    vec4 world = mat4_mul_vec4(u->model, vec4_from3(in->position, 1.0f));
    vec3 n = mat3_mul_vec3(u->normal_matrix, in->normal);
    *clip = mat4_mul_vec4(u->view_proj, world);
    float v[8] = {world.x, world.y, world.z, n.x, n.y, n.z, in->texcoord.x, in->texcoord.y};
    for (int i = 0; i < 8; i++)
        varyings[i] = v[i];
}

/* A square wave of period 1 (0, then 1), its steps blurred over a width w. */
static float square(float t, float w) { return clamp((fabsf(fract(t) - 0.5f) - 0.25f) / w + 0.5f, 0.0f, 1.0f); }

static void fragment(const void *uniforms, const sl_fragment_in *in, void *out)
{
    const fs_uniforms *u = uniforms;
    const float *v = in->varyings;
    vec2 uv = scale(vec2(v[6], v[7]), u->cells);
    vec2 w = vmax(fwidth(in, uv), vec2s(1e-4f));
    float a = square(uv.x, w.x), b = square(uv.y, w.y);
    float t = a + b - 2.0f * a * b; /* a xor b: the checker, 0 or 1 away from the edges */
    sl_gbuffer_texel *g = out;
    g->position = vec3(v[0], v[1], v[2]);
    g->normal = normalize(vec3(v[3], v[4], v[5]));
    g->kd = mix(u->kd[0], u->kd[1], t);
    g->ks = mix(u->ks[0], u->ks[1], t);
    g->alpha = -1.0f - mixf(u->roughness[0], u->roughness[1], t); /* <= -1: GGX of that roughness */
    g->depth = in->frag_coord.z;
}

static const sl_program program = {.vertex = vertex, .fragment = fragment, .varying_count = 8,
                                   .derivatives = true /* fwidth */};

int main(int argc, char **argv)
{
    int w = 320, h = 180;
    char scene_path[4096] = "";
    if (argc < 2 || argc > 4 || (argc > 2 && sscanf(argv[2], "%dx%d", &w, &h) != 2)) {
        fprintf(stderr, "usage: gbuffer_program OUT.png [WIDTHxHEIGHT] [SCENE.json]\n");
        return 2;
    }
    if (argc > 3)
        snprintf(scene_path, sizeof scene_path, "%s", argv[3]);
    else if (!sl_data_path("scenes/default.json", scene_path, sizeof scene_path)) {
        fprintf(stderr, "gbuffer_program: no softlight data directory (set SOFTLIGHT_DATA_DIR)\n");
        return 1;
    }
    sl_error err = {0};
    sl_mesh sphere = {0}, floor_mesh = {0};
    sl_gbuffer gb = {0};
    sl_scene *scene = sl_scene_open(scene_path, &err);
    sl_renderer *renderer = scene ? sl_renderer_create(scene, &(sl_renderer_options){.width = w, .height = h}, &err)
                                  : NULL;
    sl_raster *raster = sl_raster_create(&(sl_raster_desc){.threads = 0}, &err);
    bool ok = renderer && raster && sl_mesh_sphere(&sphere, 96, 48, &err) && sl_mesh_plane(&floor_mesh, &err) &&
              sl_gbuffer_resize(&gb, w, h, &err);

    sl_camera cam = {.eye = vec3(2.0f, -6.5f, 2.6f), .target = vec3(0, 0, 0.8f), .up = vec3(0, 0, 1),
                     .fovy_deg = 32.0f, .znear = 0.1f, .zfar = 50.0f};
    mat4 view_proj = sl_camera_view_proj(&cam, w, h);
    mat4 ball = mat4_translate(vec3(0, 0, 1)), ground = mat4_scale(vec3(6, 6, 1));
    vs_uniforms vs[2] = {{ball, view_proj, mat3_transpose(mat3_inverse(mat3_from_mat4(ball)))},
                         {ground, view_proj, mat3_transpose(mat3_inverse(mat3_from_mat4(ground)))}};
    fs_uniforms fs[2] = {
        {12.0f, {vec3(0, 0, 0), vec3(0.05f, 0.12f, 0.45f)}, {vec3(1.0f, 0.71f, 0.29f), vec3s(0.04f)}, {0.45f, 0.2f}},
        {12.0f, {vec3s(0.6f), vec3s(0.1f)}, {vec3s(0.04f), vec3s(0.04f)}, {0.6f, 0.4f}},
    };
    const sl_gbuffer_texel empty = {.depth = 1.0f}; /* nothing drawn: the lighting shows the sky */
    sl_draw draws[2] = {
        {.program = &program, .vs_uniforms = &vs[0], .fs_uniforms = &fs[0], .mesh = &sphere, .clear = &empty},
        {.program = &program, .vs_uniforms = &vs[1], .fs_uniforms = &fs[1], .mesh = &floor_mesh},
    };
    sl_target target = sl_gbuffer_target(&gb);
    ok = ok && sl_raster_draw_list(raster, &target, draws, 2, &err) && sl_renderer_light(renderer, &gb, &cam, &err) &&
         sl_image_write_png(argv[1], sl_renderer_display(renderer), &err);
    if (!ok)
        fprintf(stderr, "gbuffer_program: %s\n", err.msg);
    sl_gbuffer_free(&gb);
    sl_mesh_free(&sphere);
    sl_mesh_free(&floor_mesh);
    sl_raster_destroy(raster);
    sl_renderer_destroy(renderer);
    sl_scene_close(scene);
    return ok ? 0 : 1;
}
