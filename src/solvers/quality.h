/* The quality settings table (quality.c) as the solver uses it. */
#ifndef XRAD_SOLVERS_QUALITY_H
#define XRAD_SOLVERS_QUALITY_H

#include "xrad.h"

/* xrad_quality_resolve without the "quality: " prefix: the solver adds its
 * own. */
xrad_status quality_resolve(xrad_quality *q, xrad_error *err);

#endif
