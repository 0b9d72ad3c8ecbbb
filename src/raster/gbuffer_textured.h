/* gbuffer_textured.h - the G-buffer program for textured materials (gbuffer_textured.c; GLSL
 * twin: shaders/gbuffer_textured.vert/.frag) and the scene's decoded textures.
 *
 * Consumes: a material with maps (scene.h: sl_material_map), the scene's image list, a mesh with
 * texture coordinates and tangents. Produces: the same G-buffer texel as the built-in pair, with
 * kd, ks, alpha and the normal modulated by the maps; masked materials discard below the cutoff.
 * The program takes derivatives (texture() with an implicit level of detail), so it runs in 2x2
 * quads, through its multi-quad form on the span path (one call for up to 16 quads, structure of
 * arrays, derivatives between lanes; the quad form, one call a quad, is kept for programs drawn
 * without it) and through the generic rounds on the plain path; the masked variant may discard, so its depth
 * test runs after it. */
#ifndef SL_GBUFFER_TEXTURED_H
#define SL_GBUFFER_TEXTURED_H

#include <softlight/gbuffer_program.h>

#include "raster.h"
#include "texture.h"

/* Called by the fragment shader for each texture fetch when set (softlight trace): the map's
 * slot and sampler, the coordinate, its quad derivatives, the level of detail and the filtered
 * value. Runs for every lane of every quad, helpers included, on the thread drawing the tile;
 * the callee picks its pixel. */
typedef void (*sl_texture_trace_fn)(void *ctx, const sl_fragment_in *in, int slot, const sl_sampler2D *s, vec2 uv,
                                    vec2 dPdx, vec2 dPdy, float lambda, vec4 value);

/* The scene's images decoded, each once, with full mip chains; textures[i] is scene->images[i]. */
typedef struct {
    sl_texture **textures;
    int count;
    size_t bytes;              /* storage of all of them with their mips and decoded planes */
    sl_texture_trace_fn trace; /* NULL; softlight trace sets it to print the fetches of its pixel */
    void *trace_ctx;
} sl_scene_textures;

/* Decode every image the scene's materials name (sl_texture_load, `budget` bytes each, 0 = default).
 * An error names the scene, the first map that named the file and the file:
 * `textured.json: materials.leaf.kd_map: leaf.png: ...`; nothing is kept on failure. */
bool sl_scene_textures_load(const sl_scene *scene, size_t budget, sl_scene_textures *out, sl_error *err);
void sl_scene_textures_free(sl_scene_textures *t);

/* uMaps bits: SL_GBUFFER_MAP_* of softlight/gbuffer_program.h, 1 << sl_map_slot for each bound
 * sampler and SL_GBUFFER_MAP_CUTOFF for a discard below the cutoff (gbuffer_textured.c checks the
 * two numberings agree). */

typedef struct {
    mat4 uModel;
    mat4 uViewProj;
    mat3 uNormalMatrix; /* transpose(inverse(mat3(uModel))) */
    mat3 uModel3;       /* mat3(uModel): takes tangents to world space */
    vec3 uKd, uKs;
    float uAlpha;       /* Phong exponent, scaled by alpha_map.r */
    float uRoughness;   /* GGX roughness, scaled by alpha_map.r; -1 for a Phong material */
    float uMetallic;    /* >= 0: metallic-roughness per texel (uKd the base colour); -1 otherwise */
    float uOcclusionStrength; /* occlusion = 1 + strength (occlusion_map.r - 1) */
    vec3 uEmissive;     /* emission = uEmissive * emissive_map.rgb */
    sl_sampler2D uKdMap, uKsMap, uAlphaMap, uNormalMap, uMaskMap, uMetallicRoughnessMap, uOcclusionMap,
        uEmissiveMap;
    vec4 uKdMapST, uKsMapST, uAlphaMapST, uNormalMapST, uMaskMapST, uMetallicRoughnessMapST, uOcclusionMapST,
        uEmissiveMapST; /* uv * xy + zw */
    int uMaps;          /* SL_GBUFFER_MAP_* bits */
    float uAlphaCutoff;
    /* The G-buffer's extra plane (gbuffer.h sl_gbuffer_extra; GLSL: the fifth colour target), set
     * by sl_raster_scene_textured for a material that writes it; NULL: nothing written. */
    sl_gbuffer_extra *extra;
    int extra_width;
    sl_texture_trace_fn trace; /* NULL except under softlight trace */
    void *trace_ctx;
} sl_gbuffer_tex_uniforms;

/* Varyings: vWorldPos (3), vNormal (3), vTexCoord (2), vTangent (4: world xyz, handedness w). */
#define SL_GBUFFER_TEX_VARYINGS 12
void sl_gbuffer_tex_vert(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings);
void sl_gbuffer_tex_frag(const void *uniforms, const sl_fragment_in *in, void *texel); /* the reference */
/* The quad form (sl_program.fragment_quad) both programs carry: the same bits in one call a quad. */
void sl_gbuffer_tex_frag_quad(const void *uniforms, const sl_fragment_in in[4], void *const texel[4]);
/* The multi-quad form (sl_program.fragment_quads) both programs carry: the same bits, up to
 * SL_QUADS_MAX quads a call in structure-of-arrays form; what the span path calls. */
void sl_gbuffer_tex_frag_quads(const void *uniforms, const sl_fragment_quads *q);
extern const sl_program sl_gbuffer_tex_program;        /* no discard: early depth test */
extern const sl_program sl_gbuffer_tex_masked_program; /* alpha_cutoff: may discard, late depth test */

/* The sampler state a scene map asks for (what softlight-gl sets with glSamplerParameter too). */
sl_sampler_state sl_gbuffer_map_sampler(const sl_material_map *m);
/* Uniforms of one object: matrices and constants as sl_gbuffer_uniforms_init, plus the maps bound
 * to `tex` (NULL binds none). */
void sl_gbuffer_tex_uniforms_init(sl_gbuffer_tex_uniforms *u, mat4 model, mat4 view_proj, const sl_material *m,
                                  const sl_scene_textures *tex);

/* sl_raster_scene with the scene's textures: textured materials are drawn with the textured
 * programs, the others with the built-in pair as before (sl_raster_scene is this with NULL, and
 * refuses a scene with textured materials). */
bool sl_raster_scene_textured(sl_raster *r, const sl_scene *scene, const sl_scene_textures *textures,
                              const sl_camera *cam, sl_gbuffer *gb, sl_error *err);

/* A user's G-buffer fragment program (softlight/gbuffer_program.h, gbuffer_user.c): every object
 * drawn with sl_gbuffer_tex_vert and the user's function, which sees the object's material as
 * sl_gbuffer_tex_uniforms_init fills it. */
typedef struct {
    sl_gbuffer_tex_uniforms tex;      /* the vertex shader's; the source of `material` */
    sl_gbuffer_material material;     /* what the user's function reads */
    const sl_gbuffer_fragment_program *program;
    sl_gbuffer_extra *extra;          /* the G-buffer's extra plane, or NULL */
    int extra_width;
} sl_gbuffer_user_uniforms;

/* The public view of one object's material: the fields of sl_gbuffer_tex_uniforms it names. */
void sl_gbuffer_material_from(sl_gbuffer_material *out, const sl_gbuffer_tex_uniforms *u);
/* The sl_program that runs `p` behind sl_gbuffer_tex_vert, its flags from p->flags; `extra`: the
 * G-buffer has the extra plane (the program then stores into it). */
sl_program sl_gbuffer_user_program(const sl_gbuffer_fragment_program *p, bool extra);

/* sl_raster_scene_textured with `user` (NULL: the built-in programs) as every object's fragment
 * program. */
bool sl_raster_scene_program(sl_raster *r, const sl_scene *scene, const sl_scene_textures *textures,
                             const sl_gbuffer_fragment_program *user, const sl_camera *cam, sl_gbuffer *gb,
                             sl_error *err);

/* The G-buffer normal of an interpolated one, lane by lane for the two programs' vectorized
 * loops (gbuffer_shader.c's span form, gbuffer_textured.c's quad form): n / |n|, or (0, 0, 1)
 * where |n|^2 <= 1e-30; the reference shaders' `dot(n, n) > 1e-30 ? normalize(n) : vec3(0, 0, 1)`
 * with the same operations, so the same bits. */
static inline void sl_gbuffer_normal_lane(float x, float y, float z, float *nx, float *ny, float *nz)
{
    float d = x * x + y * y + z * z;
    bool ok = d > 1e-30f;
    float inv = 1.0f / sqrtf(ok ? d : 1.0f);
    *nx = ok ? x * inv : 0.0f;
    *ny = ok ? y * inv : 0.0f;
    *nz = ok ? z * inv : 1.0f;
}

#endif
