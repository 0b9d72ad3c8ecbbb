/* view_hud.c - text over the viewer's image: the heads-up display and the help overlay.
 *
 * SDL2_ttf draws each line into a surface, which becomes a texture. Most lines do not change
 * from one frame to the next (the key list never does), so each line slot keeps its text and
 * texture and is redrawn only when its text changes: the HUD costs a few texture copies per
 * frame, not a font rasterization. */
#if SL_HAVE_SDL2

#include <SDL.h>
#include <SDL_ttf.h>

#include "view_internal.h"

#include <stdlib.h>
#include <string.h>

#define SLOTS (3 * VIEW_HUD_MAX_LINES) /* the HUD, the help, the trace */
#define LINE_MAX_CHARS 160
#define PAD 6

typedef struct {
    char text[LINE_MAX_CHARS];
    SDL_Texture *texture; /* NULL for an empty line */
    SDL_Renderer *owner;  /* the renderer the texture belongs to */
    int w, h;
    bool valid;
} line_slot;

struct view_hud {
    TTF_Font *font;
    int line_height;
    line_slot slots[SLOTS];
};

view_hud *view_hud_create(const char *font_path, int point_size, sl_error *err)
{
    if (TTF_Init() != 0) { /* counted: each create has its TTF_Quit */
        sl_fail(err, SL_ERR_UNSUPPORTED, "SDL_ttf: %s", TTF_GetError());
        return NULL;
    }
    TTF_Font *font = TTF_OpenFont(font_path, point_size);
    if (!font) {
        sl_fail(err, SL_ERR_IO, "%s: %s", font_path, TTF_GetError());
        TTF_Quit();
        return NULL;
    }
    view_hud *hud = calloc(1, sizeof *hud);
    if (!hud) {
        TTF_CloseFont(font);
        TTF_Quit();
        sl_fail(err, SL_ERR_MEMORY, "out of memory for the HUD");
        return NULL;
    }
    hud->font = font;
    hud->line_height = TTF_FontLineSkip(font);
    return hud;
}

void view_hud_destroy(view_hud *hud)
{
    if (!hud)
        return;
    for (int i = 0; i < SLOTS; i++)
        if (hud->slots[i].texture)
            SDL_DestroyTexture(hud->slots[i].texture);
    TTF_CloseFont(hud->font);
    TTF_Quit();
    free(hud);
}

static void update_slot(view_hud *hud, SDL_Renderer *sdl, line_slot *slot, const char *text)
{
    if (slot->valid && slot->owner == sdl && !strncmp(slot->text, text, LINE_MAX_CHARS - 1))
        return;
    if (slot->texture)
        SDL_DestroyTexture(slot->texture);
    memset(slot, 0, sizeof *slot);
    snprintf(slot->text, sizeof slot->text, "%s", text);
    slot->valid = true;
    slot->owner = sdl;
    if (!slot->text[0])
        return;
    SDL_Color white = {235, 235, 235, 255};
    SDL_Surface *surface = TTF_RenderUTF8_Blended(hud->font, slot->text, white);
    if (!surface)
        return; /* the line is left out; the viewer goes on */
    slot->texture = SDL_CreateTextureFromSurface(sdl, surface);
    slot->w = surface->w;
    slot->h = surface->h;
    SDL_FreeSurface(surface);
}

int view_hud_text_width(view_hud *hud, const char *text)
{
    int w = 0, h = 0;
    if (!text[0] || TTF_SizeUTF8(hud->font, text, &w, &h) != 0)
        return 0;
    return w;
}

int view_hud_line_height(const view_hud *hud) { return hud->line_height; }

int view_hud_draw(view_hud *hud, SDL_Renderer *sdl, int slot_base, const char *const *lines, int count, int x, int y,
                  bool centre)
{
    if (count > VIEW_HUD_MAX_LINES)
        count = VIEW_HUD_MAX_LINES;
    int width = 0;
    for (int i = 0; i < count; i++) {
        line_slot *slot = &hud->slots[(slot_base + i) % SLOTS];
        update_slot(hud, sdl, slot, lines[i]);
        if (slot->w > width)
            width = slot->w;
    }
    int height = count * hud->line_height;
    if (centre) {
        int ow = 0, oh = 0;
        SDL_GetRendererOutputSize(sdl, &ow, &oh);
        x = (ow - width) / 2 - PAD;
        y = (oh - height) / 2 - PAD;
        if (x < 0)
            x = 0;
        if (y < 0)
            y = 0;
    }
    SDL_Rect box = {x, y, width + 2 * PAD, height + 2 * PAD};
    SDL_SetRenderDrawBlendMode(sdl, SDL_BLENDMODE_BLEND);
    SDL_SetRenderDrawColor(sdl, 0, 0, 0, 170);
    SDL_RenderFillRect(sdl, &box);
    for (int i = 0; i < count; i++) {
        line_slot *slot = &hud->slots[(slot_base + i) % SLOTS];
        if (!slot->texture)
            continue;
        SDL_Rect dst = {x + PAD, y + PAD + i * hud->line_height, slot->w, slot->h};
        SDL_RenderCopy(sdl, slot->texture, NULL, &dst);
    }
    return box.h;
}

#else
typedef int view_hud_unused; /* this file is only built with SDL2 */
#endif
