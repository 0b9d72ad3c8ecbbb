/* view_reload.c - the files a scene was loaded from, and whether any changed on disk (the
 * contract is in view_internal.h): the scene file, every mesh and model file, every image file
 * its materials name, its environment and irradiance map. cmd_view.c polls them a few times a
 * second and reloads the scene when one changed, keeping the camera.
 *
 * Modification times (with nanoseconds) rather than inotify: a few stat calls every
 * VIEW_POLL_SECONDS cost nothing, work on every file system, and see a file replaced by a
 * rename (what editors and exporters do) as well as one written in place. No SDL here. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "view_internal.h"

static long long mtime_of(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return -1;
    return (long long)st.st_mtim.tv_sec * 1000000000LL + (long long)st.st_mtim.tv_nsec + (long long)st.st_size;
}

static bool watch_add(view_watch *w, int *capacity, const char *path, sl_error *err)
{
    if (!path || !path[0])
        return true;
    for (int i = 0; i < w->count; i++)
        if (!strcmp(w->paths[i], path))
            return true;
    if (w->count == *capacity) {
        int grown = *capacity ? 2 * *capacity : 16;
        char(*paths)[SL_PATH_MAX] = realloc(w->paths, (size_t)grown * sizeof *paths);
        if (!paths)
            return sl_fail(err, SL_ERR_MEMORY, "out of memory for the watched files");
        w->paths = paths;
        long long *mtimes = realloc(w->mtimes, (size_t)grown * sizeof *mtimes);
        if (!mtimes)
            return sl_fail(err, SL_ERR_MEMORY, "out of memory for the watched files");
        w->mtimes = mtimes;
        *capacity = grown;
    }
    snprintf(w->paths[w->count], SL_PATH_MAX, "%s", path);
    w->mtimes[w->count] = mtime_of(path);
    w->count++;
    return true;
}

bool view_watch_scene(view_watch *w, const sl_scene *scene, const char *env_override, sl_error *err)
{
    view_watch_free(w);
    int capacity = 0;
    bool ok = watch_add(w, &capacity, scene->path, err);
    for (int i = 0; ok && i < scene->mesh_count; i++)
        if (scene->mesh_sources && (scene->mesh_sources[i].kind == SL_MESH_OBJ || scene->mesh_sources[i].kind == SL_MESH_MODEL))
            ok = watch_add(w, &capacity, scene->mesh_sources[i].path, err);
    for (int i = 0; ok && i < scene->image_count; i++)
        if (!scene->images[i].bytes) /* embedded images live in their model file */
            ok = watch_add(w, &capacity, scene->images[i].path, err);
    if (ok)
        ok = watch_add(w, &capacity, env_override ? env_override : scene->environment.hdr_path, err) &&
             watch_add(w, &capacity, env_override ? NULL : scene->environment.irradiance_path, err);
    if (!ok)
        view_watch_free(w);
    return ok;
}

bool view_watch_changed(view_watch *w, double now)
{
    if (now < w->next_poll || w->count == 0)
        return false;
    w->next_poll = now + VIEW_POLL_SECONDS;
    bool changed = false;
    for (int i = 0; i < w->count; i++) {
        long long t = mtime_of(w->paths[i]);
        if (t != w->mtimes[i]) {
            w->mtimes[i] = t;
            changed = true;
        }
    }
    return changed;
}

bool view_watch_file(view_watch *w, const char *path, sl_error *err)
{
    view_watch_free(w);
    int capacity = 0;
    return watch_add(w, &capacity, path, err);
}

void view_watch_free(view_watch *w)
{
    free(w->paths);
    free(w->mtimes);
    w->paths = NULL;
    w->mtimes = NULL;
    w->count = 0;
}
