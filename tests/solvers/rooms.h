/* Generic room scenes for the accuracy tests (issue 14): JSON text for
 * xrad_scene_parse, made from a fixed seed within the ranges documented at
 * the top of rooms.c. The same seed gives the same rooms, byte for byte, on
 * every machine (a splitmix64 generator, no rand()). */
#ifndef XRAD_TESTS_ROOMS_H
#define XRAD_TESTS_ROOMS_H

#include <stdint.h>

/* Rooms the generator makes (index 0 .. ROOMS_COUNT - 1); odd ones hold a
 * moving box. */
#define ROOMS_COUNT 6
/* The seed the tests use. */
#define ROOMS_SEED 14u

/* Scene time (s) the dynamic rooms are solved at first, and the frames
 * after it the tests advance by (ROOMS_FRAMES of 1 / ROOMS_FPS s). */
#define ROOMS_T0 (1.0 / 3.0)
#define ROOMS_FRAMES 3
#define ROOMS_FPS 30.0

typedef struct rooms_room {
    char name[96];         /* one line: what kind of room it is */
    char description[768]; /* sizes, lights, boxes, albedos, density: deterministic */
    char *json;            /* the scene, malloc'd (rooms_free) */
    int dynamic;           /* 1: a moving box (object "mover", with cross_density) */
    double density;        /* elements per metre of every surface */
    uint32_t elements;     /* what the scene will have (the loader's counting rule) */
} rooms_room;

/* Makes room `index` of the set drawn from `seed`; 0 on success, -1 for an
 * index out of range or no memory. */
int rooms_make(uint32_t index, uint32_t seed, rooms_room *out);

/* Frees out->json; accepts a zeroed room. */
void rooms_free(rooms_room *room);

#endif
