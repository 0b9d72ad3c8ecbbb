/* gl_twin.h - softlight-gl run as a child on a G-buffer softlight drew: the GL side of `softlight
 * check` and of the viewer's C/GL comparison (key M).
 *
 * The G-buffer's AOV files go into a private temporary directory; `softlight-gl render SCENE
 * --gbuffer DIR` lights them with shaders/lighting.frag (or the user's GLSL) from the camera that
 * drew them, with the render options given as command-line words, and writes its linear image,
 * which is read back. Rasterization is out of the picture: what differs is how the two shaders
 * evaluate. The command line links no OpenGL, so the GL side is another program: $SOFTLIGHT_GL
 * when set, else the softlight-gl beside this executable, else the one on PATH. */
#ifndef SL_APP_GL_TWIN_H
#define SL_APP_GL_TWIN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "core/error.h"
#include "core/image.h"
#include "raster/gbuffer.h"
#include "scene/scene.h"

typedef struct {
    const char *scene;             /* the scene file softlight-gl loads */
    const sl_gbuffer *gbuffer;     /* what the C side lit */
    const sl_camera *camera;       /* the camera that drew it (passed as --eye, --target, --up, --fovy) */
    const float *env_rotation_deg; /* NULL: the scene's */
    const char *glsl;              /* the user's GLSL lighting shader; NULL: shaders/lighting.frag */
    const char *const *options;    /* render options as command-line words */
    int option_count;
    const char *who;     /* the prefix of relayed warnings and of the --verbose command line */
    bool verbose;        /* print the softlight-gl command on stderr */
    bool relay_warnings; /* copy softlight-gl's warnings (not the scene's own) to stderr */
} sl_gl_twin_request;

#define SL_GL_TWIN_OPTIONS_MAX 64 /* option words a request may carry */

/* Light q->gbuffer through softlight-gl into `radiance` (allocated; row 0 = top), its NaN/Inf
 * counted in *repairs, and the GL_RENDERER string into `renderer` (may be NULL). False with one
 * line in err: softlight-gl missing or failing (its first error line: no GL, a GLSL compile
 * error), the files unwritable or unreadable. The temporary directory is always removed. */
bool sl_gl_twin_light(const sl_gl_twin_request *q, sl_image *radiance, sl_image_repairs *repairs, char *renderer,
                      size_t renderer_size, sl_error *err);

/* A word as a shell reads it back, after a space: bare when it is plain, else in single quotes. */
void sl_print_shell_word(FILE *out, const char *word);

#endif
