/* softlight/program.h - the contract between the rasterizer and C shaders: what a vertex and a
 * fragment shader see, the optional span and quad forms of a fragment shader, the program that
 * names them, and the fragment built-ins (derivatives, discard) as functions.
 *
 * A shader source that wants GLSL's spelling of the built-ins (dFdx(in, v), fwidth, discard(in),
 * texture(in, s, uv) ...) includes <softlight/glsl.h>, which writes them on top of the
 * sl_ functions here. docs/shader-api.md describes the whole contract. */
#ifndef SOFTLIGHT_PROGRAM_H
#define SOFTLIGHT_PROGRAM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <softlight/types.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SL_MAX_VARYINGS 16 /* floats a vertex shader may pass to the fragment shader */

/* Object-space attributes of one vertex, as the mesh stores them. */
typedef struct sl_vertex_in {
    sl_vec3 position;
    sl_vec3 normal;   /* (0,0,0) when the mesh has none */
    sl_vec2 texcoord; /* (0,0) when the mesh has none */
    sl_vec4 tangent;  /* xyz + handedness w (glTF TANGENT); (0,0,0,0) when the mesh has none */
    int index;        /* gl_VertexID: the vertex's index in the mesh */
} sl_vertex_in;

/* The 2x2 quad a fragment runs in (opaque: shaders reach it through the built-ins below). */
typedef struct sl_quad sl_quad;

/* What a fragment shader sees (GLSL built-ins plus the interpolated varyings). */
typedef struct sl_fragment_in {
    const float *varyings; /* varying_count floats, perspective-correct */
    sl_vec4 frag_coord;    /* gl_FragCoord: x+0.5, y+0.5, window depth in [0,1], 1/w_clip */
    bool front_facing;     /* gl_FrontFacing: counter-clockwise in window coordinates */
    int x, y;              /* the pixel, row 0 = bottom */
    /* Only for programs with `derivatives` or `discards` (NULL and 0 otherwise: then
     * the derivative built-ins return 0 and discard does nothing). */
    sl_quad *quad;         /* the quad's derivative records and discard marks */
    int lane;              /* 0..3: (x & 1) + 2 * (y & 1) */
    bool helper;           /* gl_HelperInvocation: uncovered or occluded, writes nothing */
} sl_fragment_in;

/* What a span fragment shader sees: the n fragments of one triangle in one row that
 * passed the depth test, left to right, in structure-of-arrays form (element j of
 * every array belongs to fragment j). Each value is bitwise the one the per-pixel
 * shader would get in sl_fragment_in; frag_coord.xy is (x[j] + 0.5, y + 0.5). */
#define SL_SPAN_MAX 256 /* the largest tile side: a span never leaves its tile's row */
typedef struct sl_fragment_span {
    int n;                                  /* 1 .. SL_SPAN_MAX */
    int y;                                  /* the row, row 0 = bottom */
    const int32_t *x;                       /* the columns, increasing */
    const float *varyings[SL_MAX_VARYINGS]; /* varyings[i][j]: varying i of fragment j */
    const float *frag_z;                    /* gl_FragCoord.z: window depth in [0,1] */
    const float *frag_w;                    /* gl_FragCoord.w: 1/w_clip */
    bool front_facing;
    char *row;                              /* texels of row y: fragment j's is row + x[j] * texel_size */
    size_t texel_size;
} sl_fragment_span;

/* Vertex shader: object-space attributes -> clip-space position and varyings. */
typedef void (*sl_vertex_shader)(const void *uniforms, const sl_vertex_in *in, sl_vec4 *clip, float *varyings);
/* Fragment shader: writes the whole texel (the depth test has already passed). */
typedef void (*sl_fragment_shader)(const void *uniforms, const sl_fragment_in *in, void *texel);
/* Optional span form of the same fragment shader: must leave every texel exactly as
 * `fragment` called on each fragment of the span would. */
typedef void (*sl_fragment_span_shader)(const void *uniforms, const sl_fragment_span *span);

/* Optional quad form of a derivative-taking fragment shader: one call for the four
 * lanes of a 2x2 quad (in[lane], lane = (x & 1) + 2 * (y & 1); helpers have
 * in[l].helper set), each writing its own scratch texel[lane] (which starts as the
 * target's texel), marking discards with sl_discard(&in[l]). It takes its derivatives
 * as differences between its lanes (glsl.h: sl_quad_dfdx ...), and must leave every
 * scratch texel and discard mark exactly as `fragment` run through the generic rounds
 * does (docs/shader-api.md "Quads"). */
typedef void (*sl_fragment_quad_shader)(const void *uniforms, const sl_fragment_in in[4], void *const texel[4]);

/* What a multi-quad shader sees (sl_program.fragment_quads): n quads of one triangle, in
 * structure-of-arrays form over their lanes. Lane l of quad q is element 4 q + l of every
 * per-lane array: pixel (qx[q] + (l & 1), qy[q] + (l >> 1)). Each lane's values are bitwise
 * what fragment_quad's in[l] holds for that quad (helpers included, extrapolated). The shader
 * writes texel[4 q + l] (scratch or the target's texel, as for fragment_quad) and sets
 * discarded[4 q + l] to 1 for a lane it discards (all 0 on entry). */
#define SL_QUADS_MAX 16                  /* quads a call: an 8x8 block's */
#define SL_QUAD_LANES (4 * SL_QUADS_MAX) /* lanes a call: 64 */
typedef struct sl_fragment_quads {
    int n;                                  /* quads, 1 .. SL_QUADS_MAX */
    const int32_t *qx, *qy;                 /* per quad: its lane 0's pixel (both even) */
    const float *varyings[SL_MAX_VARYINGS]; /* varyings[i][4 q + l] */
    const float *frag_z;                    /* per lane: gl_FragCoord.z */
    const float *frag_w;                    /* per lane: gl_FragCoord.w */
    const uint8_t *helper;                  /* per lane: 1 for a helper invocation */
    bool front_facing;
    void *const *texel;                     /* per lane: where the lane's texel goes */
    uint8_t *discarded;                     /* per lane: set to 1 by the shader to discard */
} sl_fragment_quads;

/* Optional multi-quad form: one call for up to SL_QUADS_MAX quads, so a shader's per-lane and
 * per-quad work runs in vector loops over 64 lanes instead of 4. Same rule as fragment_quad:
 * every texel and discard mark exactly as `fragment` run through the generic rounds leaves
 * them. Used on the span path instead of fragment_quad when both are set. */
typedef void (*sl_fragment_quads_shader)(const void *uniforms, const sl_fragment_quads *q);

typedef struct sl_program {
    sl_vertex_shader vertex;
    sl_fragment_shader fragment;
    int varying_count;                     /* 0 .. SL_MAX_VARYINGS */
    sl_fragment_span_shader fragment_span; /* NULL: the pipeline calls `fragment` per fragment; unused
                                              by programs with `derivatives` or `discards` */
    bool derivatives;                      /* the fragment shader takes derivatives (or samples with an
                                              implicit level): it runs in 2x2 quads with helpers */
    bool discards;                         /* the fragment shader may discard: depth is written after it */
    sl_fragment_quad_shader fragment_quad; /* NULL: the generic rounds (`derivatives` programs only) */
    bool quad_writes_texel;                /* fragment_quad writes every byte of the texel of each lane
                                              that does not discard, and reads none: its texels then do
                                              not start as the target's (not copied in), and a live lane
                                              of a program that cannot discard writes the target's in
                                              place */
    sl_fragment_quads_shader fragment_quads; /* NULL: fragment_quad per quad (or the rounds); needs
                                                `derivatives`; quad_writes_texel applies to it too */
    bool stores;                           /* the fragment shader stores outside its texel (GLSL's image
                                              stores: through its uniforms), only where
                                              sl_fragment_stores(in): the generic rounds then run once
                                              more, with stores on, after their fixed point. A shader
                                              that cannot discard and stores only at its own pixel may
                                              leave it off: its last round overwrites what the earlier
                                              rounds stored */
    bool writes_depth;                     /* every form of the fragment shader writes frag_coord.z
                                              (frag_z) into the target's depth field (its texel's float
                                              at sl_target.depth_offset) of each texel it writes, so a
                                              list of such programs leaves the tile's depth plane in its
                                              texels already and the tile does not copy it back */
} sl_program;

/* ---- fragment built-ins (glsl.h spells them dFdx, dFdy, fwidth, discard ...) ---- */
typedef enum sl_derivative {
    SL_DFDX_FINE,
    SL_DFDY_FINE,
    SL_DFDX_COARSE,
    SL_DFDY_COARSE,
    SL_FWIDTH_FINE,   /* |dFdxFine| + |dFdyFine| of one recorded value */
    SL_FWIDTH_COARSE, /* |dFdxCoarse| + |dFdyCoarse| */
} sl_derivative;

/* The derivative `kind` of the n (1..4) floats v, into d. Needs a program with `derivatives`;
 * elsewhere every d is 0. */
SL_API void sl_quad_derivative(const sl_fragment_in *in, sl_derivative kind, const float *v, int n, float *d);
/* Both derivatives of the n (1..4) floats v from one record: dx, dy (coarse or fine). */
SL_API void sl_quad_gradients(const sl_fragment_in *in, bool coarse, const float *v, int n, float *dx, float *dy);
/* Mark the fragment discarded: nothing of it is written. Needs a program with `discards`;
 * elsewhere it does nothing. The shader then returns, as GLSL's discard ends the invocation. */
SL_API void sl_discard(const sl_fragment_in *in);
/* Does a store outside the fragment's texel (an image store: through the uniforms) take effect
 * in this invocation? Not for a helper (as in GL), nor in a round of the generic quad rounds
 * before their fixed point, whose values may still change: a shader that stores guards each
 * store with it and sets sl_program.stores. */
SL_API bool sl_fragment_stores(const sl_fragment_in *in);

#ifdef __cplusplus
}
#endif

#endif
