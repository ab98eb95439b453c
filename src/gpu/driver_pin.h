/*
 * Keeps the Vulkan driver libraries loaded until the process exits, so that
 * LeakSanitizer runs with leak detection on see no false leaks (see
 * driver_pin.c for why).
 */
#ifndef XRAD_GPU_DRIVER_PIN_H
#define XRAD_GPU_DRIVER_PIN_H

/* Opens every ICD library named by the loader's driver manifests with
 * RTLD_NODELETE. Call before the first vkCreateInstance. Idempotent and
 * thread-safe; never fails: a manifest or library that cannot be read or
 * opened is skipped (the loader will then not use it either). */
void gpu_pin_driver(void);

#endif
