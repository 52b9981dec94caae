// The study of a scene (`corebox study SCENE --out PREFIX` writes PREFIX.json) as the lines of the
// speed-vs-accuracy panel, and where a scene's study is looked for when --study does not name one.
#pragma once

#include <string>
#include <vector>

#include "panel_data.h"
#include "scene.h"

namespace corebox {

// One line per method and precision (adaptive dp5 apart) of the runs that finished, as (force
// passes per unit time, |energy drift rate|), by cost. Throws InputError when the file cannot be read
// or is not a study.
std::vector<AccuracySeries> loadStudyCurves(const std::string& path);

// method = "auto" from a study file instead of a pilot: the fixed-step run of the study with the fewest
// force passes per unit time (the cost that carries from the machine of the study to this one) whose
// energy error per unit time, its largest excursion over the long run divided by that run's length, is
// at most half the scene's tolerance (the pilot's rule, auto_integrator.h). Returns false, with why in
// `summary`, when no run meets it. Throws InputError as loadStudyCurves.
bool chooseIntegratorFromStudy(const std::string& path, const Scene& scene, IntegratorDef* chosen, std::string* summary);

// docs/results/study_<scene stem>_<cpu|h200>.json beside the scene's assets/ directory, the one of
// this backend first ("cuda": h200); "" when there is none.
std::string findStudyFile(const Scene& scene, const std::string& backendName);

}  // namespace corebox
