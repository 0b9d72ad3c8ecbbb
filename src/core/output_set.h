/* output_set.h - the files one command writes, replaced all together or not at all.
 *
 * Every file softlight writes goes through an output set; one file is a set of one
 * (sl_write_file_atomic, sl_image_write_*). Adding a file writes its bytes to a temporary
 * beside the target and fsyncs it; nothing at the target changes until sl_output_set_commit
 * renames the temporaries into place. sl_output_set_free removes every temporary not renamed,
 * and, when nothing was committed, the directories the set made. A command adds every output,
 * commits once all were added, and frees the set on every path:
 *
 *     sl_output_set out = {0};
 *     bool ok = sl_output_set_image(&out, png, sl_image_encode_png, &display, err) &&
 *               sl_output_set_image(&out, pfm, sl_image_encode_pfm, &radiance, err) &&
 *               sl_output_set_commit(&out, err);
 *     sl_output_set_free(&out);
 *
 * Targets: a path that is a symbolic link is written through (the temporary goes beside the
 * file the link leads to and is renamed onto it; the link stays); a target that exists and is
 * not a regular file (directory, FIFO, device, socket) is refused, before anything is written.
 * A replaced file keeps its permissions; a new one gets 0666 less the umask.
 *
 * Temporaries are ".NAME.softlight-tmp.PID" beside the target NAME: hidden from a plain `ls`,
 * recognisable, and tied to the process writing them. One left by a killed run is removed by
 * the next set that writes the same target, once that PID is no longer alive (output_set.c).
 *
 * Does not: rename a set's files in one atomic step (see sl_output_set_commit), lock out another
 * process or thread writing the same target at the same time, or write to pipes and devices. */
#ifndef SL_OUTPUT_SET_H
#define SL_OUTPUT_SET_H

#include <stdbool.h>
#include <stddef.h>

#include "error.h"
#include "image.h"

typedef struct {
    char *path;   /* as the caller named it (messages) */
    char *target; /* what is replaced: path, or the file its symbolic links lead to */
    char *tmp;    /* the temporary beside target; NULL once renamed or removed */
} sl_output_file;

/* A set that captures instead of writing: a shard of a command (--shard I/N) runs the command's
 * own output code, and its partial file (core/partial.h) takes each image and directory. */
typedef bool (*sl_output_capture_fn)(void *user, const char *path, sl_image_encoder encode, const sl_image *img,
                                     sl_error *err);

/* Zero-initialise ({0}); no other set-up. */
typedef struct {
    sl_output_file *files;
    int count, capacity;
    char **dirs; /* directories sl_output_set_dir made */
    int dir_count, dir_capacity;
    bool committed;
    /* When set, sl_output_set_image and sl_output_set_dir hand what they are given to `capture`
     * (img NULL for a directory) and write nothing; sl_output_set_bytes refuses (raw bytes cannot
     * be cut into row bands); commit does nothing. */
    sl_output_capture_fn capture;
    void *capture_user;
} sl_output_set;

/* Write `size` bytes to a temporary for `path` (fsynced). Naming a target already in the set
 * drops the earlier bytes: the last one added is what is written, as with separate writes. */
bool sl_output_set_bytes(sl_output_set *set, const char *path, const void *bytes, size_t size, sl_error *err);
/* Encode `img` (sl_image_encode_png/hdr/pfm) and add it; an encoder's error names `path`. */
bool sl_output_set_image(sl_output_set *set, const char *path, sl_image_encoder encode, const sl_image *img,
                         sl_error *err);
/* Make directory `dir` (one level) unless it exists; a directory made here is removed again by
 * sl_output_set_free when the set is not committed (and it is empty). */
bool sl_output_set_dir(sl_output_set *set, const char *dir, sl_error *err);
/* Rename every temporary onto its target. False (err names the file) when a rename fails: the
 * files renamed before it stay replaced, the rest are not. */
bool sl_output_set_commit(sl_output_set *set, sl_error *err);
/* Remove the temporaries not renamed (and the directories made, if nothing was committed),
 * free the set and leave it empty. Safe on a zeroed or freed set. */
void sl_output_set_free(sl_output_set *set);

#endif
