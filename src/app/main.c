/* main.c - the softlight command line: `softlight <command> [options]`. */
#include <stdio.h>
#include <string.h>

int main(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "--help")) {
        printf("usage: softlight <command> [options]\n");
        return argc < 2;
    }
    fprintf(stderr, "softlight: unknown command '%s'\n", argv[1]);
    return 2;
}
