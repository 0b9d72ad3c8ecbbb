/* view_texture.c - the window's streaming texture (the contract is in view_internal.h): sized
 * to what is shown, locked for writing, unlocked.
 *
 * Why a file of its own: two parts write the texture and neither may call the other. The present
 * (view_present.c) uploads what is shown when it changed; the refinement (view_refine.c) lets a
 * moving frame's lighting pass tone map each row straight into it while the row is in cache
 * (view_shade.c), so that no pass reads the frame again. SDL_PIXELFORMAT_RGB888 is the 32-bit
 * XRGB8888 word that SDL's software renderer and X servers take without converting. A failure
 * goes back to the caller as an sl_error; this file calls nothing else of the viewer's. */
#if SL_HAVE_SDL2
#include <SDL.h>

#include "view_internal.h"

bool view_texture_lock(viewer *v, int w, int h, uint8_t **pixels, int *pitch, sl_error *err)
{
    if (!v->texture || v->texture_w != w || v->texture_h != h) {
        if (v->texture)
            SDL_DestroyTexture(v->texture);
        v->texture_w = v->texture_h = 0;
        v->texture = SDL_CreateTexture(v->sdl, SDL_PIXELFORMAT_RGB888, SDL_TEXTUREACCESS_STREAMING, w, h);
        if (!v->texture)
            return sl_fail(err, SL_ERR_UNSUPPORTED, "SDL texture %dx%d: %s", w, h, SDL_GetError());
        v->texture_w = w;
        v->texture_h = h;
    }
    void *p;
    if (SDL_LockTexture(v->texture, NULL, &p, pitch) != 0)
        return sl_fail(err, SL_ERR_UNSUPPORTED, "SDL texture %dx%d: %s", w, h, SDL_GetError());
    *pixels = p;
    return true;
}

void view_texture_unlock(viewer *v) { SDL_UnlockTexture(v->texture); }

#else
typedef int view_texture_unused; /* this file is only built with SDL2 */
#endif
