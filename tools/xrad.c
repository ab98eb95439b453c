#include <stdio.h>

#include "xrad.h"

int main(void)
{
    printf("xrad\n");
    return 0;
}
