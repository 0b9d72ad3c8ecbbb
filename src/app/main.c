/* main.c - the softlight command line: `softlight <command> [options]`, a table of subcommands. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "softlight/version.h"

static const struct {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} commands[] = {
    {"render", cmd_render, "render a scene to PNG / .hdr / .pfm files (and the G-buffer with --aov)"},
    {"view", cmd_view, "show a scene in an interactive window (SDL2)"},
    {"info", cmd_info, "print what a scene holds and the memory it will need"},
    {"trace", cmd_trace, "run the lighting shader for one pixel and print every intermediate value"},
    {"compare", cmd_compare, "compare two .pfm/.hdr images (error metrics, difference image)"},
    {"check", cmd_check, "shade one G-buffer with a C lighting program and its GLSL (softlight-gl); compare"},
    {"truth", cmd_truth, "the ground-truth image of a scene (brute-force integral, cached)"},
    {"merge", cmd_merge, "join the partial files of a --shard I/N run into its outputs"},
};

static void usage(FILE *out)
{
    fprintf(out, "usage: softlight <command> [options]\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(out, "  %-8s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\n`softlight --version` prints the version.\n");
    fprintf(out, "`softlight <command> --help` describes each command's options.\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("softlight %s\n", SL_VERSION_STRING);
        return 0;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (!strcmp(argv[1], commands[i].name))
            return commands[i].run(argc, argv);
    fprintf(stderr, "softlight: unknown command '%s' (try softlight --help)\n", argv[1]);
    return 2;
}
