/* commands.h - the softlight subcommands. Each takes the whole argv (argv[1] is its own name)
 * and returns the process exit status: 0 success, 1 a failed check (compare), 2 bad input or error. */
#ifndef SL_COMMANDS_H
#define SL_COMMANDS_H

int cmd_render(int argc, char **argv);
int cmd_view(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_trace(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_check(int argc, char **argv);
int cmd_truth(int argc, char **argv);
int cmd_merge(int argc, char **argv);

#endif
