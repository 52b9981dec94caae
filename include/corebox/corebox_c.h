/* corebox's C interface: the World of world.h for other languages' foreign-function interfaces
 * (Python ctypes or cffi, Rust, C#, Lua, ...) and for C programs.
 *
 * Design note.
 * - Exceptions cannot cross a C boundary, so every function returns a corebox_status: 0 on success,
 *   otherwise the code of the error (the same codes as `corebox run`'s exit status: 2 bad input or
 *   unknown id, 3 instability, 4 device, 1 anything else) and corebox_last_error() gives its message,
 *   per thread, until the next failing call on that thread. A placement that does not fit (a hard core
 *   across a wall or over another particle) is COREBOX_REJECTED with the reason, not an error of the
 *   world: nothing changed.
 * - Plain structs with fixed-size fields, vectors as double[3], ids as uint64_t; no allocation crosses
 *   the boundary: arrays read through the world (positions, ids, contacts) stay owned by it and are
 *   valid until the next call that edits or steps that world.
 * - Units and semantics are those of world.h (reduced units; a game may read them as SI).
 */
#ifndef COREBOX_COREBOX_C_H
#define COREBOX_COREBOX_C_H

#include <stddef.h>
#include <stdint.h>

#include "corebox/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum corebox_status {
    COREBOX_OK = 0,
    COREBOX_ERROR = 1,             /* anything not below (out of memory, ...) */
    COREBOX_INPUT_ERROR = 2,       /* a bad definition, file, value or id */
    COREBOX_INSTABILITY = 3,       /* the simulation blew up (non-finite values, escapes, runaway energy) */
    COREBOX_DEVICE_ERROR = 4,      /* no GPU, or a GPU failed */
    COREBOX_REJECTED = 5           /* a placement overlapped a wall or a particle; nothing changed */
} corebox_status;

typedef enum corebox_backend { COREBOX_BACKEND_CPU = 0, COREBOX_BACKEND_CUDA = 1, COREBOX_BACKEND_AUTO = 2 } corebox_backend;
typedef enum corebox_precision { COREBOX_FP64 = 0, COREBOX_FP32 = 1 } corebox_precision;

typedef struct corebox_world corebox_world; /* opaque */

/* One species (world.h ParticleSpecies). */
typedef struct corebox_species {
    const char* name;        /* unique in the world; copied */
    double mass;             /* [m] > 0 */
    double radius;           /* hard-core radius [sigma] > 0 */
    double epsilon;          /* LJ well depth; 0: no pair force */
    double sigma;            /* LJ length [sigma] */
    double acceleration[3];  /* the species' own field, added to gravity [sigma / tau^2] */
    float color[3];          /* linear RGB in [0, 1] */
} corebox_species;

/* A world's definition (world.h WorldDef) with its first species; fill with corebox_world_def_default. */
typedef struct corebox_world_def {
    double box_size[3];        /* [sigma] */
    double wall_restitution;   /* [0, 1] */
    double restitution;        /* ball-ball, [0, 1] */
    double gravity[3];         /* [sigma / tau^2] */
    corebox_species species0;  /* species 0; add more with corebox_world_add_species */
    double substep;            /* advance()'s fixed step [tau] */
    int max_substeps;          /* per advance() call */
    corebox_backend backend;
    corebox_precision precision;
    int threads;               /* CPU threads; 0: all */
    int gpus;                  /* CUDA devices; 0: the measured best */
    int device;                /* first CUDA device */
    int contact_sweeps;        /* cap on the contact solver's sweeps per listing; 0: corebox's own (16) */
    int impact_rounds;         /* cap on the impact rounds per step, 0 to 4096; 0: corebox's own (64) */
    int contact_listings;      /* cap on the contact solver's listings per step, 0 to 32; 0: corebox's own (32) */
} corebox_world_def;

typedef struct corebox_step_info {
    int substeps;
    double simulated_time, dropped_time, alpha;  /* [tau]; alpha in [0, 1) */
    int64_t pair_collisions, wall_collisions;
    double dissipated;
    double seconds;                              /* wall time of the call [s] */
    /* of seconds: the impact rounds, the contact phase, and of it the contact lists [s] */
    double seconds_impacts, seconds_contacts, seconds_listings;
    int contact_listings; /* contact lists made (all steps) */
    double overlap_left;  /* deepest overlap the contact phase left at a step's end [fraction of a contact distance] */
} corebox_step_info;

typedef struct corebox_contact {
    int is_wall;           /* 0: pair (a, b); 1: wall (a, wall_axis, wall_side) */
    uint64_t a, b;         /* b: UINT64_MAX for a wall */
    int wall_axis, wall_side;
    double time;           /* since the start of the call [tau] */
    double normal[3];      /* unit, from b to a; a wall's into the box */
    double impulse;        /* normal impulse on a [m sigma / tau] */
    double speed;          /* normal approach speed [sigma / tau] */
} corebox_contact;

typedef struct corebox_energy {
    double kinetic, potential, dissipated, external;
    double conserved;  /* kinetic + potential + dissipated - external: constant up to integration error */
    double momentum[3];
} corebox_energy;

COREBOX_API const char* corebox_version(void);
/* The message of this thread's last failing call ("" when none). */
COREBOX_API const char* corebox_last_error(void);

COREBOX_API void corebox_world_def_default(corebox_world_def* def);
COREBOX_API corebox_status corebox_world_create(const corebox_world_def* def, corebox_world** world);
/* backend: as in the definition; the scene's precision and devices apply. */
COREBOX_API corebox_status corebox_world_create_from_scene(const char* path, corebox_backend backend, corebox_world** world);
COREBOX_API void corebox_world_destroy(corebox_world* world); /* NULL is fine */

COREBOX_API corebox_status corebox_world_add_species(corebox_world* world, const corebox_species* species, int* index);
COREBOX_API corebox_status corebox_world_add_particle(corebox_world* world, int species, const double position[3],
                                                      const double velocity[3], uint64_t* id);
COREBOX_API corebox_status corebox_world_remove_particle(corebox_world* world, uint64_t id);
COREBOX_API corebox_status corebox_world_apply_impulse(corebox_world* world, uint64_t id, const double impulse[3]);
COREBOX_API corebox_status corebox_world_set_velocity(corebox_world* world, uint64_t id, const double velocity[3]);
COREBOX_API corebox_status corebox_world_set_position(corebox_world* world, uint64_t id, const double position[3]);
COREBOX_API corebox_status corebox_world_set_gravity(corebox_world* world, const double gravity[3]);
COREBOX_API corebox_status corebox_world_set_restitution(corebox_world* world, double ball_ball, double wall);

/* info may be NULL. */
COREBOX_API corebox_status corebox_world_step(corebox_world* world, double dt, corebox_step_info* info);
COREBOX_API corebox_status corebox_world_advance(corebox_world* world, double frame_time, corebox_step_info* info);

COREBOX_API size_t corebox_world_particle_count(const corebox_world* world);
/* count x 3 doubles (x, y, z per particle, slot order), and the id of each slot. */
COREBOX_API corebox_status corebox_world_positions(corebox_world* world, const double** xyz, size_t* count);
COREBOX_API corebox_status corebox_world_velocities(corebox_world* world, const double** xyz, size_t* count);
COREBOX_API corebox_status corebox_world_ids(corebox_world* world, const uint64_t** ids, size_t* count);
/* The impacts of the last step or advance. */
COREBOX_API corebox_status corebox_world_contacts(corebox_world* world, const corebox_contact** contacts, size_t* count);
/* Ids within radius of centre, ascending; writes at most capacity, *found is the full count. */
COREBOX_API corebox_status corebox_world_query_radius(corebox_world* world, const double centre[3], double radius, uint64_t* ids,
                                                      size_t capacity, size_t* found);
COREBOX_API corebox_status corebox_world_energy(corebox_world* world, corebox_energy* energy);
COREBOX_API corebox_status corebox_world_state_hash(corebox_world* world, uint64_t* hash);

#ifdef __cplusplus
}
#endif

#endif
