/* The C interface (corebox_c.h), compiled as C: create, add, reject, kick, step, read, query, errors. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "corebox/corebox_c.h"

static int failures = 0;
#define CHECK(cond)                                                      \
    do {                                                                 \
        if (!(cond)) {                                                   \
            fprintf(stderr, "%s:%d: failed: %s\n", __FILE__, __LINE__, #cond); \
            ++failures;                                                  \
        }                                                                \
    } while (0)

int main(void) {
    corebox_world_def def;
    corebox_world_def_default(&def);
    CHECK(def.box_size[1] == 60.0 && def.species0.radius == 0.5);
    corebox_world* world = NULL;
    CHECK(corebox_world_create(&def, &world) == COREBOX_OK);
    if (!world) return 1;

    uint64_t first = 0, second = 0, blocked = 0;
    const double a[3] = {10, 10, 10}, b[3] = {12, 10, 10}, over[3] = {10.5, 10, 10}, still[3] = {0, 0, 0};
    CHECK(corebox_world_add_particle(world, 0, a, still, &first) == COREBOX_OK);
    CHECK(corebox_world_add_particle(world, 0, b, NULL, &second) == COREBOX_OK);
    CHECK(second == first + 1);
    CHECK(corebox_world_add_particle(world, 0, over, still, &blocked) == COREBOX_REJECTED);
    CHECK(strstr(corebox_last_error(), "overlap") != NULL);
    CHECK(corebox_world_particle_count(world) == 2);

    const double kick[3] = {0, 5, 0};
    CHECK(corebox_world_apply_impulse(world, first, kick) == COREBOX_OK);
    corebox_energy e;
    CHECK(corebox_world_energy(world, &e) == COREBOX_OK);
    CHECK(fabs(e.momentum[1] - 5.0) < 1e-12);

    corebox_step_info info;
    CHECK(corebox_world_advance(world, 1.0 / 60.0, &info) == COREBOX_OK);
    CHECK(info.substeps == 4);
    CHECK(info.contact_listings == 0 && info.overlap_left == 0.0); /* two balls in the air: nothing touches */
    CHECK(info.seconds_impacts >= 0 && info.seconds_listings >= 0 && info.seconds_listings <= info.seconds_contacts);
    CHECK(info.seconds_impacts + info.seconds_contacts <= info.seconds);
    const double* xyz = NULL;
    size_t n = 0;
    CHECK(corebox_world_positions(world, &xyz, &n) == COREBOX_OK);
    CHECK(n == 2 && xyz != NULL);
    CHECK(xyz[1] > 10.0);  /* kicked up faster than gravity pulls it down in 1/60 s */
    CHECK(xyz[4] < 10.0);  /* the other fell */

    /* A ball at rest on the floor: the contact solver lists it every step and leaves (almost) no overlap. */
    uint64_t resting = 0;
    const double floorSpot[3] = {20, 0.5, 20};
    CHECK(corebox_world_add_particle(world, 0, floorSpot, still, &resting) == COREBOX_OK);
    CHECK(corebox_world_step(world, 1.0 / 240.0, &info) == COREBOX_OK);
    CHECK(info.contact_listings == 1);
    CHECK(info.overlap_left >= 0.0 && info.overlap_left < 1e-3);
    CHECK(corebox_world_remove_particle(world, resting) == COREBOX_OK);

    uint64_t found[4];
    size_t count = 0;
    const double centre[3] = {12, 10, 10};
    CHECK(corebox_world_query_radius(world, centre, 0.5, found, 4, &count) == COREBOX_OK);
    CHECK(count == 1 && found[0] == second);

    CHECK(corebox_world_remove_particle(world, 999) == COREBOX_INPUT_ERROR);
    CHECK(strstr(corebox_last_error(), "999") != NULL);
    CHECK(corebox_world_set_restitution(world, 2.0, 0.5) == COREBOX_INPUT_ERROR);
    CHECK(corebox_world_step(world, -1.0, NULL) == COREBOX_INPUT_ERROR);
    CHECK(corebox_world_step(NULL, 0.1, NULL) == COREBOX_INPUT_ERROR);

    const corebox_contact* contacts = NULL;
    CHECK(corebox_world_contacts(world, &contacts, &count) == COREBOX_OK);
    corebox_world_destroy(world);

    corebox_world_def bad;
    corebox_world_def_default(&bad);
    bad.species0.mass = 0;
    corebox_world* none = NULL;
    CHECK(corebox_world_create(&bad, &none) == COREBOX_INPUT_ERROR && none == NULL);
    CHECK(strstr(corebox_last_error(), "mass") != NULL);
    corebox_world_def_default(&bad);
    CHECK(bad.contact_sweeps == 0 && bad.impact_rounds == 0 && bad.contact_listings == 0); /* corebox's own caps */
    bad.impact_rounds = 5000;
    CHECK(corebox_world_create(&bad, &none) == COREBOX_INPUT_ERROR && none == NULL);
    CHECK(strstr(corebox_last_error(), "impactRounds") != NULL);
    bad.impact_rounds = 0;
    bad.contact_sweeps = -1;
    CHECK(corebox_world_create(&bad, &none) == COREBOX_INPUT_ERROR && none == NULL);
    CHECK(strstr(corebox_last_error(), "contactSweeps") != NULL);
    bad.contact_sweeps = 0;
    bad.contact_listings = 33;
    CHECK(corebox_world_create(&bad, &none) == COREBOX_INPUT_ERROR && none == NULL);
    CHECK(strstr(corebox_last_error(), "contactListings") != NULL);
    CHECK(strlen(corebox_version()) >= 5);

    if (failures) fprintf(stderr, "%d check(s) failed\n", failures);
    else printf("corebox_c.h: all checks passed (corebox %s)\n", corebox_version());
    return failures ? 1 : 0;
}
