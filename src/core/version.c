/* The library's version, as built (include/xrad_version.h). */
#include "xrad.h"

const char *xrad_version(void) { return XRAD_VERSION; }
