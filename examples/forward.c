/* forward.c - a forward fragment shader: your own vertex and fragment shader in C, drawn by
 * softlight's rasterizer into your own render target, then written as a PNG.
 *
 * The fragment shader is Blinn-Phong under one light, on a procedural pattern of bands that
 * stays sharp but never aliases: fwidth() (GLSL's derivative built-in, computed over 2x2 quads
 * as on a GPU) gives the width of a pixel in the pattern's units.
 *
 *   forward OUT.png [WIDTHxHEIGHT] [MESH.obj]
 *
 * The mesh defaults to softlight's scenes/meshes/bunny.obj when the data directory has it,
 * else a sphere. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <softlight/glsl.h>
#include <softlight/softlight.h>

typedef struct { mat4 model, view_proj; } vs_uniforms;
typedef struct { vec3 eye, light_dir, base, stripe; float bands; } fs_uniforms;
typedef struct { vec3 color; float depth; } texel; /* the target: a colour and a depth a pixel */

static void vertex(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    const vs_uniforms *u = uniforms;
    vec4 world = mat4_mul_vec4(u->model, vec4_from3(in->position, 1.0f));
    vec3 n = xyz(mat4_mul_vec4(u->model, vec4_from3(in->normal, 0.0f))); /* uniform scale only */
    *clip = mat4_mul_vec4(u->view_proj, world);
    varyings[0] = world.x, varyings[1] = world.y, varyings[2] = world.z; /* vWorldPos */
    varyings[3] = n.x, varyings[4] = n.y, varyings[5] = n.z;             /* vNormal */
}

static void fragment(const void *uniforms, const sl_fragment_in *in, void *out)
{
    const fs_uniforms *u = uniforms;
    vec3 p = vec3(in->varyings[0], in->varyings[1], in->varyings[2]);
    vec3 n = normalize(vec3(in->varyings[3], in->varyings[4], in->varyings[5]));
    vec3 v = normalize(sub(u->eye, p));
    if (!in->front_facing)
        n = scale(n, -1.0f);
    /* Bands along z, their edges blurred over one pixel's width of the pattern. */
    float s = p.z * u->bands;
    float w = fwidth(in, s);
    float edge = fabsf(fract(s) - 0.5f) * 2.0f; /* 0 at a band's centre, 1 at its edge */
    vec3 albedo = mix(u->base, u->stripe, smoothstep(0.5f - w, 0.5f + w, edge));
    /* Blinn-Phong, with a little ambient. */
    vec3 h = normalize(add(u->light_dir, v));
    float diffuse = maxf(dot(n, u->light_dir), 0.0f);
    float specular = diffuse > 0.0f ? powf(maxf(dot(n, h), 0.0f), 60.0f) : 0.0f;
    vec3 c = add(scale(albedo, 0.15f + 0.85f * diffuse), vec3s(0.4f * specular));
    ((texel *)out)->color = c;
}

static const sl_program program = {.vertex = vertex, .fragment = fragment, .varying_count = 6,
                                   .derivatives = true /* fwidth */};

int main(int argc, char **argv)
{
    int w = 320, h = 180;
    char mesh_path[4096];
    if (argc < 2 || argc > 4 || (argc > 2 && sscanf(argv[2], "%dx%d", &w, &h) != 2)) {
        fprintf(stderr, "usage: forward OUT.png [WIDTHxHEIGHT] [MESH.obj]\n");
        return 2;
    }
    sl_error err = {0};
    sl_mesh mesh = {0};
    bool ok;
    if (argc > 3)
        ok = sl_mesh_load_obj(argv[3], &mesh, &err);
    else if (sl_data_path("scenes/meshes/bunny.obj", mesh_path, sizeof mesh_path) &&
             sl_mesh_load_obj(mesh_path, &mesh, NULL))
        ok = true;
    else
        ok = sl_mesh_sphere(&mesh, 64, 32, &err);
    sl_raster *raster = ok ? sl_raster_create(&(sl_raster_desc){.threads = 0}, &err) : NULL;
    if (!raster) {
        fprintf(stderr, "forward: %s\n", err.msg);
        return 1;
    }
    /* Fit the mesh into a unit box at the origin, standing a Y-up OBJ upright in a Z-up world. */
    vec3 lo = mesh.positions[0], hi = lo;
    for (int i = 1; i < mesh.vertex_count; i++)
        lo = vmin(lo, mesh.positions[i]), hi = vmax(hi, mesh.positions[i]);
    vec3 size = sub(hi, lo);
    float s = 2.0f / maxf(size.x, maxf(size.y, size.z));
    mat4 model = mat4_mul(mat4_rotate(vec3(1, 0, 0), radians(90.0f)),
                          mat4_mul(mat4_scale(vec3s(s)), mat4_translate(scale(add(lo, hi), -0.5f))));
    vec3 eye = vec3(-2.2f, -3.0f, 1.2f);
    vs_uniforms vu = {model, mat4_mul(perspective(radians(35.0f), (float)w / (float)h, 0.1f, 20.0f),
                                      lookAt(eye, vec3(0, 0, 0), vec3(0, 0, 1)))};
    fs_uniforms fu = {eye, normalize(vec3(-0.5f, -1.0f, 1.0f)), vec3(0.85f, 0.55f, 0.25f),
                      vec3(0.2f, 0.35f, 0.7f), 8.0f};

    /* The target: w x h texels, row 0 at the bottom, depth in each texel; cleared by the draw. */
    texel *texels = malloc((size_t)w * (size_t)h * sizeof *texels);
    const texel clear = {vec3(0.08f, 0.09f, 0.11f), 1.0f};
    sl_target target = {.width = w, .height = h, .texel_size = sizeof(texel), .texels = texels,
                        .depth_offset = offsetof(texel, depth)};
    sl_draw draw = {.program = &program, .vs_uniforms = &vu, .fs_uniforms = &fu, .mesh = &mesh,
                    .cull = SL_CULL_NONE, .clear = &clear};
    sl_image img = {0};
    ok = texels && sl_raster_draw(raster, &target, &draw, &err) && sl_image_alloc(&img, w, h, 3, &err);
    for (int y = 0; ok && y < h; y++) /* image row 0 is the top; sRGB-ish gamma for display */
        for (int x = 0; x < w; x++) {
            vec3 c = clamp(texels[(size_t)(h - 1 - y) * (size_t)w + (size_t)x].color, 0.0f, 1.0f);
            float *px = &img.data[((size_t)y * (size_t)w + (size_t)x) * 3];
            px[0] = powf(c.x, 1.0f / 2.2f), px[1] = powf(c.y, 1.0f / 2.2f), px[2] = powf(c.z, 1.0f / 2.2f);
        }
    ok = ok && sl_image_write_png(argv[1], &img, &err);
    if (!ok)
        fprintf(stderr, "forward: %s\n", texels ? err.msg : "out of memory");
    sl_image_free(&img);
    free(texels);
    sl_raster_destroy(raster);
    sl_mesh_free(&mesh);
    return ok ? 0 : 1;
}
