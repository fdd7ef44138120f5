/* main.c - the pliant command-line tool (being written). */
#include <stdio.h>
int main(void)
{
    fprintf(stderr, "pliant: not yet\n");
    return 1;
}
