#include "collision_rounds.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace corebox {
namespace {

// Sweeps run in batches between convergence checks (RelaxationPlan): where the host drives the sweeps, a
// check reads a residual back from the device.
constexpr int kSweepBatch = 8;
// A relaxation that started from overlaps deeper than this fraction of a diameter lists again, up to
// CollisionSettings::maxListings times. Those listings are not wasted: in the landing of the 40,000-ball pile (CPU,
// fp32, the first 2.6 s, 615 steps, 421 of them listing again, 938 listings after the first) every later listing held
// pairs the one before did not, 195 / 1139 / 3685 of them at the 10th / 50th / 90th percentile: the sweeps' position
// moves bring neighbours within the resting gap. So listing again only when an unlisted pair touches would save no
// listing. 2% of a diameter, not 0.5%: at 10^6 balls some pair of the landing pile always starts a listing deeper than
// 0.5%, so nearly every step listed again (up to 5 listings a step, each with its sweeps over the whole pile) to mend a
// few pairs. `corebox bench pile` (an H200, fp32, the same call, 0.5% / 1% / 2%): 10^6 balls 58.5 / 53.5 / 49.8 ms a
// frame (the last second 40.8 / 41.2 / 40.8), the largest overlap at the end 3e-4 / 3e-4 / 5e-4 of a diameter, rest
// at 2.20 s in each; 10^5 balls 14.8 against 13.0 (0.5% / 2%), overlap 3e-4 in both. The CPU here (2 threads, 0.5% /
// 2%): 10,000 balls 1.25 / 1.0 listings a step, 55.8 / 56.6 ms a frame (fp32) and 58.9 / 54.9 (fp64), overlaps within
// 5e-5 in both, the same rest times. Not deeper: with the impact rounds' cell lists skipped and sorted by counting (an
// H200, fp32, one call, 2% / 3.5% / 5%) 10^6 balls took 47.2 / 45.4 / 44.3 ms a frame, 10^5 11.0 / 10.6 / 10.4, the
// sandbox example at 10^5 balls 13.6 / 12.2 / 12.4, the piles as sound, but random dense configurations handed to the
// stage (tests/physics/test_dense_contact.cpp, 12 sweeps a listing) were left with overlaps of 1.7% to 2.5% of a
// diameter from 3% on, where the tests allow 1%: the last listing's sweeps halve what it started from, about.
constexpr double kDeepOverlap = 0.02;
// A listing that is listed again (its overlaps deeper than kDeepOverlap) runs at most kRelistSweeps
// sweeps: the next listing warm-starts from what they leave and sweeps on, over the pairs the moves
// brought into contact. In a landing every listing ran to the sweep cap (16), 2.5 listings a step at
// 10^6 balls. `corebox bench pile` (an H200, fp32, the same call, with no cap of their own / 4 / 8):
// 10^6 balls 43.4 / 42.8 / 42.1 ms a frame (the last second 34.4 / 34.4 / 34.6), 1.33 / 1.48 / 1.35
// listings and 21.2 / 17.8 / 18.7 sweeps a step, the largest overlap at the end 4.5e-4 / 2.8e-4 / 2.6e-4
// of a diameter, rest at 2.20 / 2.30 / 2.22 s; 10^5 balls 10.6 / 10.3 / 10.3, 10^4 5.5 / 5.5 / 5.5; the
// sandbox example at 10^5 balls 12.4 / 12.2 (4) ms a frame. Here (2 threads, no cap / 8, fp32 and fp64):
// 10,000 balls 53.9 / 53.0 and 52.5 / 50.0 ms a frame, overlaps 3.5e-5 / 2.1e-5 and 4.7e-5 / 2.1e-5,
// the same rest times; 2,000 balls list again too seldom to differ.
constexpr int kRelistSweeps = 8;
// Contacts closing slower than what kRestingSteps steps of gravity add (kRestingSteps g dt) rest
// (restitution 0, the contact phase) instead of bouncing as impacts. A bounce from that speed would
// rise (kRestingSteps g dt)^2 / (2 g): at 6 g dt 18 g dt^2, 0.3% of a diameter at dt = 1/240. With 2 g dt, a
// settled pile of frictionless balls, which goes on compacting slowly, kept up about a thousand such
// slow impacts a step, resolved one matching a round (`corebox bench pile`, 5 s): the 10,000-ball
// pile hit the 64-round cap in 298 of its 1200 steps (CPU fp64, 105 ms a frame); with 6 g dt in 9
// (89 ms a frame), and an H200's 10^5-ball pile (fp32) in 313 steps instead of 1048. The piles came to
// rest as before, with smaller overlaps (10,000 balls: 2.4e-4 of a diameter before, 4.8e-5 after).
// 12 g dt (a lost bounce from it would rise 72 g dt^2, 1.2% of a diameter at dt = 1/240, e^2 of that
// with restitution e): the settled pile still jittered at about 4 g dt (kinetic energy 0.017 a ball),
// and those slow approaches kept the impact rounds at 8 a step. An H200, fp32, `corebox bench pile`,
// 5 s, the same call with 6 / 12 / 24 g dt: 10^5 balls 24.7 / 21.1 / 17.0 ms a frame (the last second
// 10.9 / 9.5 / 9.3), 25.8 / 16.3 / 9.4 impact rounds a step, 186 / 4 / 0 steps at the round cap, the
// kinetic energy at 5 s 1618 / 741 / 522, the largest overlap 5e-4 / 2e-4 / 2e-4 of a diameter, rest
// at 2.25 / 2.20 / 2.18 s; 10^6 balls 96.7 / 79.6 / 70.1 ms a frame (53.2 / 48.4 / 49.9), 242 / 27 / 0
// capped steps; the sandbox example at 10^5 balls 19.2 / 17.1 / 17.9 ms of simulation a frame. Not
// 24: a bounce lost from 24 g dt rises 5% of a diameter, which a dropped ball shows.
constexpr double kRestingSteps = 12.0;

}  // namespace

CollisionSettings collisionSettingsFor(const InteractionDef& interaction, double dt, double smallestContact) {
    CollisionSettings settings;
    settings.maxRounds = interaction.maxCollisionRounds;
    if (interaction.contactSweeps > 0) settings.maxSweepsJacobi = settings.maxSweepsGaussSeidel = interaction.contactSweeps;
    if (interaction.contactListings > 0) settings.maxListings = interaction.contactListings;
    settings.dt = dt;
    const double g = std::sqrt(interaction.gravity[0] * interaction.gravity[0] + interaction.gravity[1] * interaction.gravity[1] +
                               interaction.gravity[2] * interaction.gravity[2]);
    settings.restingSpeed = kRestingSteps * g * dt;
    // A contact still approaching at a tenth of what one step of gravity adds (or of the
    // elastic-below speed, without gravity) is at rest: what is left closes g dt^2 / 10 in a step,
    // which the position level of the next step removes.
    settings.speedTolerance = 0.1 * std::max(g * dt, interaction.elasticBelowSpeed);
    // Gravity presses a resting stack into its base by g dt^2 / 2 a step, and what the position level
    // leaves of it is left at every contact up the stack: a quarter of it, not 1e-3 of a contact
    // distance (a warm-started Jacobi relaxation on the H200 left a column of ten balls 1.6e-3 lower).
    // Not below 1e-5: five times fp32's contact slack (collision.h), what fp32 positions resolve.
    if (g > 0 && smallestContact > 0)
        settings.overlapTolerance = std::min(settings.overlapTolerance, std::max(1e-5, 0.25 * g * dt * dt / smallestContact));
    return settings;
}

void resolveCollisions(Backend& backend, const CollisionSettings& settings, StepReport& report) {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    // 0. The backend's screen of the positions in its last force pass. Nothing near contact: the round
    // that would find nothing is the screen itself.
    // A contact that began at the very start of the step rewinds by dt up to rounding (in fp32, the
    // rounding of a position against a depth of v dt): a tenth of a step of room keeps it an impact.
    const ImpactWindow<double> window{1.1 * settings.dt, settings.restingSpeed};
    report.screen = backend.screenStage(window, settings.restingSpeed * settings.dt);
    if (report.screen == StageScreen::Quiet) {
        report.rounds = 1;
        report.secondsImpacts = std::chrono::duration<double>(Clock::now() - start).count();
        return;
    }
    // 1. Impacts.
    backend.beginCollisions(window);
    bool settled = false;
    if (report.screen == StageScreen::WallsOnly) {  // no pair can meet: the walls at once, no round-by-round waits
        const int rounds = backend.resolveWallImpacts();
        if (rounds >= 0) {
            report.rounds = rounds;
            settled = true;
        }
    }
    if (!settled && settings.maxRounds > 0) {
        const ImpactRounds rounds = backend.runImpactRounds(settings.maxRounds);
        report.rounds = rounds.rounds;
        settled = rounds.settled;
    }
    if (!settled) report.roundCapHit = backend.findEvents(EventScope::All) > 0;
    const CollisionTally tally = backend.collisionTally();
    report.pairCollisions = tally.pairCollisions;
    report.wallCollisions = tally.wallCollisions;
    report.dissipated = tally.dissipated;
    report.impulses = tally.impulses;
    const Clock::time_point impactsDone = Clock::now();
    report.secondsImpacts = std::chrono::duration<double>(impactsDone - start).count();

    // 2. Contacts. Deep overlaps (handed in, or left by a capped impact phase) move particles by a
    // good part of a diameter, into neighbours that were not listed: list again after such a pass.
    double kinetic0 = 0, liftWork = 0;  // kinetic0: only read when something was listed (a reduction)
    ContactResidual<double> residual{0, 0};
    for (int listing = 0; listing < settings.maxListings; ++listing) {
        const Clock::time_point listingStart = Clock::now();
        const int64_t listed = backend.listContacts(RestingContact<double>{settings.restingSpeed, settings.restingSpeed * settings.dt});
        report.secondsListings += std::chrono::duration<double>(Clock::now() - listingStart).count();
        if (listed == 0) break;
        ++report.contactListings;
        if (report.contacts == 0) kinetic0 = backend.kineticEnergy();  // listing changes no velocity
        report.contacts = std::max(report.contacts, listed);
        // The first sweep alone, to see how deep the overlaps were; then batches.
        const int maxSweeps = backend.relaxesGaussSeidel() ? settings.maxSweepsGaussSeidel : settings.maxSweepsJacobi;
        report.contactListingsJacobi += backend.relaxesGaussSeidel() ? 0 : 1;
        RelaxationPlan plan{maxSweeps, kSweepBatch, settings.speedTolerance, settings.overlapTolerance};
        // Listed again (known at the listing where the backend measures it there, else after the first
        // sweep): Gauss-Seidel sweeps, on which kRelistSweeps was measured, and not the last listing allowed.
        const double listedDepth = backend.listedOverlap();
        if (backend.relaxesGaussSeidel() && listing + 1 < settings.maxListings) {
            if (listedDepth >= kDeepOverlap) {
                plan.maxSweeps = std::min(plan.maxSweeps, kRelistSweeps);
            } else if (listedDepth < 0) {
                plan.relistOverlap = kDeepOverlap;
                plan.relistSweeps = kRelistSweeps;
            }
        }
        const RelaxationOutcome relaxed = backend.relaxListing(plan);
        residual = relaxed.last;
        // Counted against the sweep cap: a listing stopped at kRelistSweeps is listed again, not left.
        if (relaxed.sweeps >= maxSweeps) {
            report.contactCappedSpeed += residual.speedChange > plan.speedTolerance;
            report.contactCappedOverlap += residual.overlap > plan.overlapTolerance;
        }
        const double firstOverlap = backend.listedOverlap() >= 0 ? backend.listedOverlap() : relaxed.first.overlap;
        report.contactSweeps += relaxed.sweeps;
        backend.endRelaxation();
        liftWork += backend.contactLiftWork();
        report.impulses += backend.contactImpulses();  // a resting pile's weight reaches the floor here
        if (firstOverlap < kDeepOverlap) break;
    }
    report.contactOverlap = residual.overlap;
    if (report.contacts > 0) report.dissipated += (kinetic0 - backend.kineticEnergy()) - liftWork;
    report.secondsContacts = std::chrono::duration<double>(Clock::now() - impactsDone).count();
}

}  // namespace corebox
