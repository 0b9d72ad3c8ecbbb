/* test_output_set.c - src/core/output_set.c: the files of one command replaced all together or
 * not at all, symbolic links written through, non-regular targets refused, and the temporaries
 * of killed runs removed.
 *
 * Each test works in a fresh directory of its own and checks every entry in it, hidden ones
 * included, so a stray temporary fails the test. A "disk full" is a file size limit
 * (RLIMIT_FSIZE, SIGXFSZ ignored: write() fails with EFBIG), which needs no root. */
#include "testutil.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/output_set.h"

/* A fresh directory test_tmpdir()/name; returns it in `dir` (512 bytes). */
static void fresh_dir(char *dir, const char *name)
{
    snprintf(dir, 512, "%s/%s", test_tmpdir(), name);
    assert_int_equal(mkdir(dir, 0755), 0);
}

static const char *in(const char *dir, const char *name)
{
    static char slots[8][1200];
    static int next;
    char *p = slots[next++ % 8];
    int n = snprintf(p, sizeof slots[0], "%s/%s", dir, name);
    assert_true(n > 0 && (size_t)n < sizeof slots[0]);
    return p;
}

/* The file's contents as a string (at most 255 bytes); "" when it cannot be read. */
static const char *contents(const char *path)
{
    static char buf[256];
    buf[0] = '\0';
    FILE *f = fopen(path, "rb");
    if (f) {
        size_t n = fread(buf, 1, sizeof buf - 1, f);
        buf[n] = '\0';
        fclose(f);
    }
    return buf;
}

/* How many entries `dir` holds (hidden ones included, . and .. not). */
static int entries(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    closedir(d);
    return n;
}

static bool add_text(sl_output_set *set, const char *path, const char *text, sl_error *err)
{
    return sl_output_set_bytes(set, path, text, strlen(text), err);
}

/* One output failing replaces none, and leaves no temporary. */
static void test_all_or_none(void **state)
{
    (void)state;
    char dir[512];
    fresh_dir(dir, "none");
    test_write_bytes(in(dir, "a.png"), "old a", 5);
    test_write_bytes(in(dir, "b.hdr"), "old b", 5);
    sl_output_set set = {0};
    sl_error err = {0};
    assert_true(add_text(&set, in(dir, "a.png"), "new a", &err));
    assert_true(add_text(&set, in(dir, "b.hdr"), "new b", &err));
    assert_false(add_text(&set, in(dir, "missing/c.pfm"), "new c", &err));
    assert_msg_contains(err, "missing/c.pfm: cannot create a temporary file beside it");
    sl_output_set_free(&set);
    assert_string_equal(contents(in(dir, "a.png")), "old a");
    assert_string_equal(contents(in(dir, "b.hdr")), "old b");
    assert_int_equal(entries(dir), 2);

    /* the disk fills up during the third file: the first two are not replaced either */
    struct rlimit old_limit, small;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
    small = old_limit;
    small.rlim_cur = 1000;
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    static unsigned char big[20000];
    assert_true(add_text(&set, in(dir, "a.png"), "new a", &err));
    assert_true(add_text(&set, in(dir, "b.hdr"), "new b", &err));
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
    bool ok = sl_output_set_bytes(&set, in(dir, "c.pfm"), big, sizeof big, &err);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old_limit), 0);
    signal(SIGXFSZ, old_handler);
    assert_false(ok);
    assert_msg_contains(err, "c.pfm: write failed after 1000 of 20000 bytes");
    sl_output_set_free(&set);
    assert_string_equal(contents(in(dir, "a.png")), "old a");
    assert_string_equal(contents(in(dir, "b.hdr")), "old b");
    assert_int_equal(entries(dir), 2);

    /* a directory the set made is removed again; an existing one is kept */
    assert_true(sl_output_set_dir(&set, in(dir, "aov"), &err));
    assert_true(add_text(&set, in(dir, "aov/x.pfm"), "x", &err));
    assert_true(sl_output_set_dir(&set, dir, &err));
    sl_output_set_free(&set);
    assert_int_equal(entries(dir), 2);

    /* all added: all replaced, the directory made stays */
    assert_true(add_text(&set, in(dir, "a.png"), "new a", &err));
    assert_true(sl_output_set_dir(&set, in(dir, "aov"), &err));
    assert_true(add_text(&set, in(dir, "aov/x.pfm"), "x", &err));
    assert_true(add_text(&set, in(dir, "b.hdr"), "new b", &err));
    assert_string_equal(contents(in(dir, "a.png")), "old a"); /* nothing changes before the commit */
    assert_true(sl_output_set_commit(&set, &err));
    sl_output_set_free(&set);
    assert_string_equal(contents(in(dir, "a.png")), "new a");
    assert_string_equal(contents(in(dir, "b.hdr")), "new b");
    assert_string_equal(contents(in(dir, "aov/x.pfm")), "x");
    assert_int_equal(entries(dir), 3);
    assert_int_equal(entries(in(dir, "aov")), 1);
}

/* The commit renames the first file added last: when a later rename fails, the main output
 * is still the old one. The same target named twice keeps the later bytes. */
static void test_commit_order(void **state)
{
    (void)state;
    char dir[512];
    fresh_dir(dir, "order");
    test_write_bytes(in(dir, "main.png"), "old", 3);
    sl_output_set set = {0};
    sl_error err = {0};
    assert_true(add_text(&set, in(dir, "main.png"), "new", &err));
    assert_true(add_text(&set, in(dir, "side.hdr"), "side", &err));
    assert_int_equal(mkdir(in(dir, "side.hdr"), 0755), 0); /* in the way after the add */
    assert_false(sl_output_set_commit(&set, &err));
    assert_msg_contains(err, "side.hdr: cannot rename the temporary file into place");
    sl_output_set_free(&set);
    assert_string_equal(contents(in(dir, "main.png")), "old");
    assert_int_equal(entries(dir), 2);
    assert_int_equal(rmdir(in(dir, "side.hdr")), 0);

    assert_true(add_text(&set, in(dir, "main.png"), "first", &err));
    assert_true(add_text(&set, in(dir, "main.png"), "second", &err));
    assert_int_equal(set.count, 1);
    assert_true(sl_output_set_commit(&set, &err));
    sl_output_set_free(&set);
    assert_string_equal(contents(in(dir, "main.png")), "second");
    assert_int_equal(entries(dir), 1);
}

/* A symbolic link is written through and stays a link (relative, chained, dangling);
 * the target keeps its mode; FIFOs, directories and devices are refused and left alone. */
static void test_links_and_special_files(void **state)
{
    (void)state;
    char dir[512];
    fresh_dir(dir, "links");
    assert_int_equal(mkdir(in(dir, "real"), 0755), 0);
    test_write_bytes(in(dir, "real/file.png"), "old", 3);
    assert_int_equal(chmod(in(dir, "real/file.png"), 0640), 0);
    assert_int_equal(symlink("real/file.png", in(dir, "link.png")), 0);
    assert_int_equal(symlink("link.png", in(dir, "link2.png")), 0);
    sl_error err = {0};
    assert_true(sl_write_file_atomic(in(dir, "link2.png"), "new", 3, &err));
    struct stat st;
    assert_int_equal(lstat(in(dir, "link2.png"), &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    assert_int_equal(lstat(in(dir, "link.png"), &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    assert_int_equal(lstat(in(dir, "real/file.png"), &st), 0);
    assert_true(S_ISREG(st.st_mode));
    assert_int_equal(st.st_mode & 0777, 0640);
    assert_string_equal(contents(in(dir, "real/file.png")), "new");
    assert_int_equal(entries(in(dir, "real")), 1);

    /* a link to a name not there yet: the name is created, the link stays */
    assert_int_equal(symlink("real/later.png", in(dir, "dangling.png")), 0);
    assert_true(sl_write_file_atomic(in(dir, "dangling.png"), "later", 5, &err));
    assert_int_equal(lstat(in(dir, "dangling.png"), &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    assert_string_equal(contents(in(dir, "real/later.png")), "later");

    /* a link to itself */
    assert_int_equal(symlink("loop.png", in(dir, "loop.png")), 0);
    assert_false(sl_write_file_atomic(in(dir, "loop.png"), "x", 1, &err));

    /* non-regular targets: refused with what they are, left as they were */
    assert_int_equal(mkfifo(in(dir, "fifo.png"), 0644), 0);
    assert_false(sl_write_file_atomic(in(dir, "fifo.png"), "x", 1, &err));
    assert_int_equal(err.code, SL_ERR_IO);
    assert_msg_contains(err, "fifo.png: is a FIFO, not a regular file");
    assert_int_equal(lstat(in(dir, "fifo.png"), &st), 0);
    assert_true(S_ISFIFO(st.st_mode));
    assert_false(sl_write_file_atomic(in(dir, "real"), "x", 1, &err));
    assert_msg_contains(err, "real: is a directory, not a regular file");
    assert_int_equal(symlink("/dev/null", in(dir, "null.png")), 0);
    assert_false(sl_write_file_atomic(in(dir, "null.png"), "x", 1, &err));
    assert_msg_contains(err, "null.png: is a symbolic link to a character device, not a regular file");
    assert_int_equal(lstat(in(dir, "null.png"), &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    assert_int_equal(stat("/dev/null", &st), 0);
    assert_true(S_ISCHR(st.st_mode));
    /* links, FIFO, real/: nothing else appeared (no temporaries) */
    assert_int_equal(entries(dir), 7);
    assert_int_equal(entries(in(dir, "real")), 2);
}

/* A PID that is not running: a child that has exited and been reaped. */
static pid_t dead_pid(void)
{
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0)
        _exit(0);
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    return pid;
}

/* Temporaries of a killed run are named for the target and the PID, and the next set
 * writing that target removes those whose PID is gone (and overwrites one with its own PID,
 * left by a dead process that had it before). */
static void test_stale_temporaries(void **state)
{
    (void)state;
    char dir[512], name[128];
    fresh_dir(dir, "stale");
    pid_t dead = dead_pid();
    snprintf(name, sizeof name, ".out.png.softlight-tmp.%ld", (long)dead);
    test_write_bytes(in(dir, name), "stale", 5);
    snprintf(name, sizeof name, ".out.png.softlight-tmp.%ld", (long)getppid()); /* alive */
    test_write_bytes(in(dir, name), "live", 4);
    snprintf(name, sizeof name, ".other.png.softlight-tmp.%ld", (long)dead); /* another target */
    test_write_bytes(in(dir, name), "other", 5);
    snprintf(name, sizeof name, ".out.png.softlight-tmp.%ldx", (long)dead); /* not a PID */
    test_write_bytes(in(dir, name), "odd", 3);
    snprintf(name, sizeof name, ".out.png.softlight-tmp.%ld", (long)getpid()); /* ours, but stale */
    test_write_bytes(in(dir, name), "mine", 4);

    /* while the set is pending, its temporary is there under the recognisable name */
    sl_output_set set = {0};
    sl_error err = {0};
    assert_true(add_text(&set, in(dir, "out.png"), "new", &err));
    assert_string_equal(contents(in(dir, name)), "new");
    snprintf(name, sizeof name, ".out.png.softlight-tmp.%ld", (long)dead);
    assert_int_equal(access(in(dir, name), F_OK), -1);
    assert_true(sl_output_set_commit(&set, &err));
    sl_output_set_free(&set);
    assert_string_equal(contents(in(dir, "out.png")), "new");
    /* out.png, the live one, the other target's, the odd name */
    assert_int_equal(entries(dir), 4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_or_none),
        cmocka_unit_test(test_commit_order),
        cmocka_unit_test(test_links_and_special_files),
        cmocka_unit_test(test_stale_temporaries),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
