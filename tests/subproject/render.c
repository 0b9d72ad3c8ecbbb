/* render.c - a parent project's program using softlight built in its tree (add_subdirectory):
 * loads a scene or a model, renders it and writes the tone-mapped image as a PNG.
 *
 *   render SCENE.json|MODEL OUT.png WIDTH HEIGHT */
#include <stdio.h>
#include <stdlib.h>

#include "core/image.h"
#include "render/renderer.h"
#include "scene/scene.h"

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: render SCENE OUT.png WIDTH HEIGHT\n");
        return 2;
    }
    sl_scene scene = {0};
    sl_renderer renderer = {0};
    sl_render_desc desc = {0};
    sl_option_set_size(&desc.options, atoi(argv[3]), atoi(argv[4]));
    sl_error err = {0};
    bool ok = sl_scene_load(argv[1], &scene, &err) && sl_renderer_init(&renderer, &scene, &desc, &err) &&
              sl_renderer_frame(&renderer, NULL, &err) && sl_image_write_png(argv[2], &renderer.display, &err);
    if (ok)
        printf("rendered %s -> %s (%dx%d)\n", argv[1], argv[2], renderer.display.width, renderer.display.height);
    else
        fprintf(stderr, "render: %s\n", err.msg);
    sl_renderer_free(&renderer);
    sl_scene_free(&scene);
    return ok ? 0 : 1;
}
