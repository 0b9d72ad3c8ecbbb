/* slgl.h - softlight-gl's internals: the same frame as softlight, drawn by OpenGL.
 *
 * softlight-gl exists to check softlight: it renders a scene with the GLSL originals in shaders/
 * (gbuffer.vert/.frag, lighting.frag) on whatever OpenGL the machine has (Mesa's llvmpipe on a
 * server), headless, and writes the same files as `softlight render`. Everything that is not
 * rasterization or shading -- scene loading, camera matrices, the environment's mip source, the
 * Hammersley set, the SH9 irradiance, image files, the tone map -- is softlight's own C code, so a
 * difference between the two images can only come from those two stages.
 *
 * Stages (one file each):
 *   context.c        EGL on the surfaceless platform, a 3.3 core context, no window, no surface
 *   program.c        compile and link shaders from files, with their logs in the error
 *   gbuffer_pass.c   meshes -> G-buffer textures (RGBA32F x4 + DEPTH32F), read back as an sl_gbuffer;
 *                    or an sl_gbuffer (from softlight's AOV files) uploaded into the same textures;
 *                    textured materials drawn with gbuffer_textured.vert/.frag
 *   textures.c       the scene's decoded images -> GL textures (same formats, GL's mips), sampler state
 *   shadow_pass.c    meshes -> the shadow maps of the lights that cast (R32F view depths,
 *                    shaders/shadow_depth.vert/.frag, shadow_sun.frag), src/shadow's maps drawn by GL
 *   lighting_pass.c  G-buffer textures + environment + uniforms + shadow maps -> RGBA32F
 *                    radiance, read back
 *   main.c           the command line
 * Functions shared across these files are prefixed slgl_. */
#ifndef SLGL_H
#define SLGL_H

#include <stdbool.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include "core/error.h"
#include <softlight/glsl.h>
#include "core/image.h"
#include "ibl/ibl.h"
#include "raster/gbuffer.h"
#include "raster/gbuffer_textured.h"
#include "raster/raster.h"
#include "scene/scene.h"
#include "shading/lighting.h"

/* ---- context.c ---- */
typedef struct {
    EGLDisplay display;
    EGLContext context;
    const char *renderer; /* GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" */
    const char *version;  /* GL_VERSION */
} slgl_context;

/* Create a headless OpenGL 3.3 core context and make it current; false with one line when EGL,
 * the surfaceless platform or a suitable context is missing. */
bool slgl_context_create(slgl_context *ctx, sl_error *err);
void slgl_context_destroy(slgl_context *ctx);
/* SL_ERR_GL with the pending glGetError, naming `what`; true when there is none. */
bool slgl_check(const char *what, sl_error *err);

/* ---- program.c ---- */
/* Compile shaders/<vert> and shaders/<frag> (slgl_shader_dir) into a
 * linked program; the compiler's log is in err on failure. */
bool slgl_program_from_files(const char *vert_name, const char *frag_name, GLuint *program, sl_error *err);
/* A program from a file fragment shader and a vertex shader given as source (the full-screen triangle);
 * frag_defines (NULL: none), "#define NAME VALUE" lines, are compiled after the file's #version. */
bool slgl_program_from_sources(const char *vert_label, const char *vert_src, const char *frag_name,
                               const char *frag_defines, GLuint *program, sl_error *err);
/* A user's lighting shader (--lighting my.frag, whose first line is #version 330 core), compiled
 * after shaders/lighting.frag with its main renamed and with frag_defines (lighting.frag's
 * specialization), so the file may use the built-in's uniforms and functions; errors name the file
 * and line they are in (one line, no "does not compile" prefix: the log names the file). */
bool slgl_program_user_lighting(const char *vert_label, const char *vert_src, const char *user_path,
                                const char *frag_defines, GLuint *program, sl_error *err);
/* The full-screen triangle's vertex shader: (-1,-1), (3,-1), (-1,3) from gl_VertexID, no buffer
 * (the lighting and occlusion passes). */
extern const char *const slgl_fullscreen_vert;
/* shaders/<vert_name> linked with the fragment shader at `frag_path`, a file the command line
 * names (not in the shader directory). */
bool slgl_program_with_fragment_file(const char *vert_name, const char *frag_path, GLuint *program, sl_error *err);
/* The directory shaders are read from: $SL_SHADER_DIR when set, else shaders/ in the data directory. */
const char *slgl_shader_dir(void);

/* ---- gbuffer_pass.c ---- */
/* The four colour targets and the depth target of the G-buffer, width x height, row 0 = bottom. */
typedef struct {
    int width, height;
    GLuint fbo;
    GLuint position, normal, kd, ks_alpha; /* RGBA32F; position.w = 1 where covered */
    GLuint depth;                          /* DEPTH_COMPONENT32F */
    GLuint extra;                          /* RGBA32F occlusion + emission; 0 unless asked for */
    GLuint cone;                           /* RGBA32F bent normal + AO: the occlusion pass's
                                              (slgl_occlusion.cone, not owned) or cone_files;
                                              0 without either */
    GLuint cone_files;                     /* the cone uploaded from G-buffer files (owned) */
    GLuint program;                        /* gbuffer.vert/.frag: untextured materials */
    GLuint tex_program;                    /* gbuffer_textured.vert/.frag: materials with maps */
    GLuint samplers[SL_MAP_COUNT];         /* one per texture unit = map slot */
    GLuint user_program;                   /* --gbuffer-shader: gbuffer_textured.vert and the user's
                                              fragment shader, for every object; 0 = none */
    bool user_extra;                       /* the user's shader writes oExtra (location 4) */
    bool facet;                            /* normal.w and kd.w hold the facet normal (gbuffer.frag's
                                              facet_code): drawn by softlight's own programs, or
                                              uploaded from a G-buffer with its facet plane */
} slgl_gbuffer;

typedef struct {
    GLuint vao, vbo_position, vbo_normal, vbo_texcoord, vbo_tangent, ibo;
    int index_count;
} slgl_mesh;

/* ---- textures.c ---- */
/* The scene's textures in GL: names[i] is sl_scene_textures.textures[i]. */
typedef struct {
    GLuint *names;
    int count;
} slgl_textures;

/* Upload each texture's level 0 in its own GL format (GL_SRGB8_ALPHA8 for SL_TEX_SRGB8_ALPHA8, ...)
 * and glGenerateMipmap the rest. */
bool slgl_textures_upload(const sl_scene_textures *in, slgl_textures *out, sl_error *err);
void slgl_textures_destroy(slgl_textures *t);
/* A sampler object's state from softlight's (filters, wrap, LOD bias and clamps). */
void slgl_sampler_set(GLuint sampler, const sl_sampler_state *s);

/* `extra`: a fifth target for the extra channels (occlusion, emission: src/raster/gbuffer.h), for a
 * scene with a material that writes them. */
bool slgl_gbuffer_create(slgl_gbuffer *g, int width, int height, bool extra, sl_error *err);
void slgl_gbuffer_destroy(slgl_gbuffer *g);
/* --gbuffer-shader: draw every object with gbuffer_textured.vert and the fragment shader at
 * `frag_path` (docs/gbuffer-programs.md "softlight-gl"), its uniforms the textured program's. */
bool slgl_gbuffer_use_fragment(slgl_gbuffer *g, const char *frag_path, sl_error *err);
/* Upload every mesh of the scene; `meshes` has scene->mesh_count entries. */
bool slgl_meshes_upload(const sl_scene *scene, slgl_mesh *meshes, sl_error *err);
void slgl_meshes_destroy(slgl_mesh *meshes, int count);
/* The G-buffer pass: clear, then draw every object: with gbuffer.vert/.frag, or, when its material
 * has maps, with gbuffer_textured.vert/.frag on `textures` (the GL twins of `sl_textures`, the
 * renderer's, which give the uniforms their map bits as for softlight's draw). */
bool slgl_gbuffer_draw(slgl_gbuffer *g, const sl_scene *scene, const slgl_mesh *meshes,
                       const sl_scene_textures *sl_textures, const slgl_textures *textures, mat4 view_proj,
                       sl_error *err);
/* Read the targets back into `out` (allocated here, row 0 = bottom like softlight's G-buffer). */
bool slgl_gbuffer_read(const slgl_gbuffer *g, sl_gbuffer *out, sl_error *err);
/* Fill the targets from softlight's G-buffer instead of drawing (--gbuffer DIR). */
bool slgl_gbuffer_upload(slgl_gbuffer *g, const sl_gbuffer *in, sl_error *err);

/* ---- occlusion_pass.c ---- */
/* Ambient occlusion (src/occlusion/gtao.h) drawn by shaders/gtao.frag over the half-resolution
 * grid and shaders/gtao_blur.frag over the image, into the G-buffer's extra target. */
typedef struct {
    int width, height, grid_width, grid_height;
    GLuint program, blur_program, vao;
    GLuint half, half_fbo; /* RGBA32F, the grid: AO, unnormalised bent normal */
    GLuint out, out_fbo;   /* RGBA32F: occlusion x AO, emission; copied into the extra target */
    GLuint cone;           /* RGBA32F, the out_fbo's second target: bent normal, AO per texel (the
                              lighting's uCone) */
} slgl_occlusion;

bool slgl_occlusion_create(slgl_occlusion *o, int width, int height, sl_error *err);
void slgl_occlusion_destroy(slgl_occlusion *o);
/* Multiply the extra target's occlusion by the AO within `radius` of the frame `cam` drew, and
 * hand the lighting the cone target (g->cone). */
bool slgl_occlusion_draw(slgl_occlusion *o, slgl_gbuffer *g, const sl_camera *cam, float radius, sl_error *err);

/* ---- shadow_pass.c ---- */
/* The shadow maps lighting.frag reads (src/shadow/shadow.h), one texture per kind of map. */
typedef struct {
    GLuint program;        /* shadow_depth.vert/.frag */
    GLuint fbo, depth;     /* the target: a layer of a map texture + a DEPTH_COMPONENT32F renderbuffer */
    int side;              /* SL_SHADOW_CUBE_SIZE + 2 SL_SHADOW_GUARD */
    GLuint cubes;          /* the point lights' cube maps: R32F 2D array, side x side, six layers per
                              casting light (+X, -X, +Y, -Y, +Z, -Z); 0 when none casts */
    int cube_count;        /* casting point lights */
    int cube_layer[SL_LIGHTING_MAX_LIGHTS]; /* light i's first layer; -1: it casts none */
    GLuint sun_program;    /* shadow_depth.vert + shadow_sun.frag */
    GLuint sun_fbo, sun_depth; /* the env lights' target: a layer of suns + its own depth buffer */
    GLuint suns;           /* the env lights' maps: R32F 2D array, SL_SHADOW_SUN_SIZE a side, layer
                              k = map k; 0 when no env light casts */
    sl_shadow_suns sun_frames; /* their clusters and frames (sl_shadow_suns_frames; no depths):
                              count = the layers, env_light_sun = each env light's */
    GLuint sky_program;    /* shadow_depth.vert + shadow_sun.frag (the sky maps' own) */
    GLuint sky_fbo, sky_depth; /* the sky maps' target: a layer of sky + its own depth buffer */
    GLuint sky;            /* the sky visibility maps: R32F 2D array, SL_SKY_MAP_SIZE a side, layer
                              k = map k; 0 when there are none */
    sl_shadow_sky sky_frames; /* their directions, weights m_k and frames (sl_shadow_sky_frames; no
                              depths): count = the layers */
    GLuint mask_sampler;   /* a masked caster's coverage map's state while the maps are drawn */
} slgl_shadows;

/* Draw the maps of the scene's lights that cast (point light i when `all` is set or its "shadow"
 * key is, as sl_shadow_build chooses) from the uploaded meshes; none when no light casts. With
 * `all` and env lights (NULL: none), the env lights' maps too, clustered and framed by
 * sl_shadow_suns_frames as sl_shadow_suns_build does (env_rotation_deg: the lighting's). With
 * sky_maps K > 0, the K sky visibility maps, weighted by sky_env (what the diffuse irradiance
 * holds: the renderer's choice, src/render/renderer.c update_sky) and framed by
 * sl_shadow_sky_frames as sl_shadow_sky_build does. A masked caster (src/raster/coverage.h, from
 * sl_textures) casts where its mask keeps it, its map read from `textures` (NULL: every caster
 * opaque). */
bool slgl_shadows_draw(slgl_shadows *s, const sl_scene *scene, const slgl_mesh *meshes,
                       const sl_scene_textures *sl_textures, const slgl_textures *textures, bool all,
                       const sl_env_lights *env_lights, float env_rotation_deg, int sky_maps, const sl_env *sky_env,
                       sl_error *err);
/* Free the maps; s is left empty (no light casts), which a zeroed struct is not. */
void slgl_shadows_destroy(slgl_shadows *s);

/* ---- lighting_pass.c ---- */
/* What one lighting program is compiled for (lighting.frag "Specialization"): the resolved options
 * and the scene's features, each an SL_* #define of that program. */
typedef struct {
    int lod_rule, distortion, gterm, estimator, diffuse, specular, rotate, env_layout, irradiance_method;
    int lod_rule_ggx, distortion_ggx, estimator_ggx; /* the GGX set's (uEstimatorGGX ...) */
    int env_lights_ggx_only; /* uEnvLightsGGXOnly */
    int point_lights; /* uPointLights and at least one light */
    int has_extra;    /* the G-buffer has the extra target */
    int env_lights;   /* at least one env light */
    int phong, ggx;   /* the microfacet sets the G-buffer holds (slgl_lighting_set_lobes) */
    int shadow_cubes; /* point lights on and at least one with a cube shadow map */
    int shadow_suns;  /* env lights and at least one env-light map */
    int sky_maps;     /* the diffuse term and the sky visibility maps */
} slgl_lighting_key;

#define SLGL_LIGHTING_PROGRAMS 8 /* programs kept; the oldest goes when a ninth is asked for */

typedef struct {
    int width, height;
    slgl_lighting_key keys[SLGL_LIGHTING_PROGRAMS];
    GLuint programs[SLGL_LIGHTING_PROGRAMS]; /* lighting.frag per key, built on first use */
    int program_count, program_next;
    bool phong, ggx;       /* the lobe sets to compile for; both until slgl_lighting_set_lobes */
    bool general;          /* $SL_GL_GENERAL set: one unspecialized program (what the C port reads) */
    const char *user_frag; /* --lighting my.frag: the user's shader instead of lighting.frag's main
                              (NULL: the built-in); its NaN/Inf pixels read back as magenta */
    GLuint vao, fbo;
    GLuint color;          /* RGBA32F radiance, a = 0 where the shader repaired a NaN/Inf */
    GLuint env;            /* level 0 + glGenerateMipmap */
    int env_levels;        /* GL's level count for that size */
    GLuint irradiance_map; /* every irradiance map (BRUTE, MAP, OCT, DP); 0 for SH9 */
    GLuint env_residual;   /* uEnvResidual: the environment less its env lights, or the octahedral
                              chain of what the samples read; 0 = env itself */
    int residual_levels;   /* its level count */
    bool residual_oct;     /* it is octahedral: every level uploaded, read with texelFetch */
    GLuint ubo;            /* HammersleyBlock */
    GLuint splitsum_phong, splitsum_ggx, splitsum_lut; /* --estimator splitsum (0 otherwise) */
    int splitsum_levels;   /* the chains' level count */
    GLuint env_dist, env_dist_marginal; /* --estimator mis: uEnvDist, uEnvDistMarginal (0 otherwise) */
    const sl_env_dist *env_dist_source; /* the distribution they hold, uploaded by the first draw
                              that asks for it (slgl_lighting_draw); NULL after a new environment */
    const float *env_dist_cdf; /* ... and its CDF array: a rebuilt distribution in the same
                              struct (other env lights) has a new one */
    const slgl_shadows *shadows; /* the maps the lights read (not owned); NULL: none casts */
} slgl_lighting;

bool slgl_lighting_create(slgl_lighting *l, int width, int height, sl_error *err);
void slgl_lighting_destroy(slgl_lighting *l);
/* Upload the environment's level 0 (mipmapped by GL) and, for BRUTE/MAP, the irradiance map. */
/* residual: the environment less its env lights (sl_env_lights.residual), or NULL when there are none. */
bool slgl_lighting_set_environment(slgl_lighting *l, const sl_env *env, const sl_env *residual,
                                   const sl_irradiance *irr, sl_error *err);
/* Upload the split-sum chains of both lobe sets (level by level, as softlight prefiltered them)
 * and the BRDF's table (src/shading/splitsum_lut.h); phong NULL: none (another estimator). */
bool slgl_lighting_set_splitsum(slgl_lighting *l, const sl_env *phong, const sl_env *ggx, const sl_splitsum_lut *lut,
                                sl_error *err);
/* The microfacet sets the lit pixels use (at least one): the programs compiled from now on leave
 * the other set's code out. */
void slgl_lighting_set_lobes(slgl_lighting *l, bool phong, bool ggx);
/* The shadow maps the next draws read (NULL: none); they must be those of the uniforms' lights
 * (sl_lighting_uniforms.shadowMaps casts for the same lights, else the draw fails). */
void slgl_lighting_set_shadows(slgl_lighting *l, const slgl_shadows *s);
/* Run lighting.frag over the G-buffer with softlight's uniforms, through the program specialized
 * for them (compiled on first use). */
bool slgl_lighting_draw(slgl_lighting *l, const slgl_gbuffer *g, const sl_lighting_uniforms *u, sl_error *err);
/* Read the radiance back into `radiance` (allocated when empty; row 0 = top); *repaired counts
 * the pixels the shader zeroed for being non-finite (the built-in), or, for a user's shader, the
 * non-finite pixels written here as magenta, as softlight's pass writes a C program's. */
bool slgl_lighting_read(const slgl_lighting *l, sl_image *radiance, long *repaired, sl_error *err);

#endif
