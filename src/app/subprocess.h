/* subprocess.h - run another program and wait for it, its output into files: what the command line
 * does to compile a program (program_load.c, the system C compiler) and to run the GL side of a
 * check (cmd_check.c, softlight-gl). One place for posix_spawn, its redirections and the wait. */
#ifndef SL_APP_SUBPROCESS_H
#define SL_APP_SUBPROCESS_H

/* Run argv (argv[0] looked up on PATH when it has no slash) with stdout into out_path and stderr
 * into err_path, or into out_path too when err_path is NULL (files created or truncated). Its exit
 * status, or -1 when it could not be started or did not exit normally. */
int sl_spawn_wait(char *const argv[], const char *out_path, const char *err_path);

#endif
