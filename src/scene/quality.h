/* The quality settings table (quality.c): the scene parser checks a
 * scene's "quality" block against it, the solvers resolve theirs with it. */
#ifndef XRAD_SCENE_QUALITY_H
#define XRAD_SCENE_QUALITY_H

#include "xrad.h"

/* xrad_quality_resolve without the "quality: " prefix: the solver adds its
 * own. */
xrad_status quality_resolve(xrad_quality *q, xrad_error *err);

#endif
