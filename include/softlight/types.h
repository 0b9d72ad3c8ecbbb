/* softlight/types.h - the plain data types every public header shares: float vectors and
 * matrices, the integer vector, and errors as values.
 *
 * The vectors are plain structs of floats (no padding): sl_vec3 is 12 bytes, x, y, z. Matrices
 * are column-major like GLSL and OpenGL: m.c[col].x is row 0 of that column, and an sl_mat4 can
 * be handed to glUniformMatrix4fv without transposing. A shader source that wants GLSL's
 * spelling of them (vec3, mat4, dot, normalize ...) includes <softlight/glsl.h>.
 *
 * A function that can fail takes an `sl_error *` (may be NULL), fills it with a code and one
 * line of text naming the file and the place, and returns false or NULL. The library never exits
 * or aborts on bad input. */
#ifndef SOFTLIGHT_TYPES_H
#define SOFTLIGHT_TYPES_H

#include <softlight/version.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sl_vec2 { float x, y; } sl_vec2;
typedef struct sl_vec3 { float x, y, z; } sl_vec3;
typedef struct sl_vec4 { float x, y, z, w; } sl_vec4;
typedef struct sl_mat3 { sl_vec3 c[3]; } sl_mat3; /* c[column] */
typedef struct sl_mat4 { sl_vec4 c[4]; } sl_mat4; /* c[column] */
typedef struct sl_ivec2 { int x, y; } sl_ivec2;

typedef enum sl_error_code {
    SL_OK = 0,
    SL_ERR_IO,          /* open, read, write, rename failed */
    SL_ERR_FORMAT,      /* malformed or truncated file */
    SL_ERR_UNSUPPORTED, /* well-formed but not something softlight handles */
    SL_ERR_RANGE,       /* a parameter or value outside what makes sense */
    SL_ERR_MEMORY,      /* allocation failed or a size would overflow */
    SL_ERR_GL,          /* no EGL / OpenGL context, or a GL call failed */
} sl_error_code;

typedef struct sl_error {
    sl_error_code code;
    char msg[512]; /* one line, NUL-terminated */
} sl_error;

/* The matrices a program's uniforms are usually made of (GL conventions: view down -Z, NDC z in
 * [-1, 1]). A singular matrix inverts to all zeros. */
SL_API sl_mat4 sl_mat4_inverse(sl_mat4 m);
/* Rotation by `angle` radians about the unit `axis`, right-handed. */
SL_API sl_mat4 sl_mat4_rotate(sl_vec3 axis, float angle);
/* gluLookAt: the view matrix of an eye at `eye` looking at `center`. */
SL_API sl_mat4 sl_mat4_look_at(sl_vec3 eye, sl_vec3 center, sl_vec3 up);
/* gluPerspective: fovy in radians; maps z in [-near, -far] to NDC [-1, 1]. */
SL_API sl_mat4 sl_mat4_perspective(float fovy, float aspect, float znear, float zfar);

#ifdef __cplusplus
}
#endif

#endif
