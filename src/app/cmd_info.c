/* cmd_info.c - `softlight info scene.json`: what a scene holds and the memory a frame of it needs. */
#include <stdio.h>

#include "args.h"
#include "commands.h"
#include "core/image.h"
#include "raster/gbuffer.h"
#include "scene/scene.h"

static void print_vec3(const char *label, vec3 v)
{
    printf("  %-10s (%g, %g, %g)\n", label, (double)v.x, (double)v.y, (double)v.z);
}

int cmd_info(int argc, char **argv)
{
    const sl_arg table[] = {0};
    const char *positional[1];
    int npos;
    bool help;
    sl_error err = {0};
    if (!sl_args_parse(argc, argv, 2, table, 0, positional, 1, &npos, &help, &err)) {
        fprintf(stderr, "softlight info: %s\n", err.msg);
        return 2;
    }
    if (help || npos != 1) {
        sl_args_print_help(help ? stdout : stderr, "softlight info SCENE.json", table, 0);
        return help ? 0 : 2;
    }
    sl_scene scene;
    if (!sl_scene_load(positional[0], &scene, &err)) {
        fprintf(stderr, "softlight info: %s\n", err.msg);
        return 2;
    }

    long vertices = 0, triangles = 0;
    size_t mesh_bytes = 0;
    for (int i = 0; i < scene.mesh_count; i++) {
        const sl_mesh *m = &scene.meshes[i];
        mesh_bytes += (size_t)m->vertex_count * (2 * sizeof(vec3) + (m->texcoords ? sizeof(vec2) : 0)) +
                      (size_t)m->triangle_count * 3 * sizeof(uint32_t);
    }
    for (int i = 0; i < scene.object_count; i++) {
        const sl_mesh *m = &scene.meshes[scene.objects[i].mesh];
        vertices += m->vertex_count;
        triangles += m->triangle_count;
    }

    printf("scene %s\n", scene.path);
    printf("  objects    %d (%ld triangles, %ld vertices drawn; %d distinct meshes)\n", scene.object_count,
           triangles, vertices, scene.mesh_count);
    for (int i = 0; i < scene.object_count; i++) {
        const sl_object *o = &scene.objects[i];
        const sl_material *mat = &scene.materials[o->material];
        printf("    [%d] %-12s %7d triangles  material %s (kd %.3g %.3g %.3g, ks %.3g %.3g %.3g, alpha %g)\n", i,
               o->name, scene.meshes[o->mesh].triangle_count, mat->name, (double)mat->kd.x, (double)mat->kd.y,
               (double)mat->kd.z, (double)mat->ks.x, (double)mat->ks.y, (double)mat->ks.z, (double)mat->alpha);
    }
    printf("  materials  %d\n", scene.material_count);
    printf("  lights     %d point light%s\n", scene.light_count, scene.light_count == 1 ? "" : "s");
    vec3 lo, hi;
    if (sl_scene_bounds(&scene, &lo, &hi)) {
        print_vec3("bounds min", lo);
        print_vec3("bounds max", hi);
    }
    const sl_camera *c = &scene.camera;
    print_vec3("eye", c->eye);
    print_vec3("target", c->target);
    printf("  fovy       %g degrees, near %g, far %g\n", (double)c->fovy_deg, (double)c->znear, (double)c->zfar);

    const sl_render_settings *s = &scene.settings;
    printf("  render     %dx%d, N = %d samples, exposure %g, contrast %g\n", s->width, s->height, s->samples,
           (double)s->exposure, (double)s->contrast);

    size_t env_bytes = 0;
    if (scene.environment.hdr_path[0]) {
        sl_image env;
        if (!sl_image_read_hdr(scene.environment.hdr_path, &env, NULL, &err)) {
            fprintf(stderr, "softlight info: %s\n", err.msg);
            sl_scene_free(&scene);
            return 2;
        }
        /* A full mip chain adds a third to level 0. */
        env_bytes = (size_t)env.width * (size_t)env.height * sizeof(vec3) * 4 / 3;
        printf("  environment %s: %dx%d, intensity %g, rotation %g degrees%s%s\n", scene.environment.hdr_path,
               env.width, env.height, (double)scene.environment.intensity, (double)scene.environment.rotation_deg,
               scene.environment.irradiance_path[0] ? ", irradiance " : "", scene.environment.irradiance_path);
        sl_image_free(&env);
    } else {
        printf("  environment none (black)\n");
    }

    size_t pixels = (size_t)s->width * (size_t)s->height;
    size_t gbuffer_bytes = pixels * sizeof(sl_gbuffer_texel);
    size_t frame_bytes = pixels * (3 * sizeof(float) + 4); /* linear radiance + 8-bit output */
    double mib = 1024.0 * 1024.0;
    printf("  memory     G-buffer %.1f MiB (%zu B/pixel), frame %.1f MiB, environment + mips %.1f MiB, "
           "meshes %.1f MiB\n",
           (double)gbuffer_bytes / mib, sizeof(sl_gbuffer_texel), (double)frame_bytes / mib, (double)env_bytes / mib,
           (double)mesh_bytes / mib);
    sl_scene_free(&scene);
    return 0;
}
