#include "lammps_peer.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace corebox {
namespace {

namespace fs = std::filesystem;

std::string onPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    if (!path) return "";
    std::stringstream dirs(path);
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
        const fs::path candidate = fs::path(dir) / name;
        if (!dir.empty() && access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
    return "";
}

void writeDataFile(const fs::path& path, const Scene& scene, const ParticleState& state) {
    std::ofstream out(path);
    out.precision(17);
    out << "corebox starting state for the LAMMPS peer of `corebox bench md`\n\n"
        << state.size() << " atoms\n1 atom types\n\n"
        << "0 " << scene.box.size[0] << " xlo xhi\n0 " << scene.box.size[1] << " ylo yhi\n0 " << scene.box.size[2] << " zlo zhi\n\n"
        << "Masses\n\n1 " << scene.species[0].mass << "\n\nAtoms # atomic\n\n";
    for (size_t i = 0; i < state.size(); ++i) {
        const Vec3<double>& x = state.position[i];
        out << i + 1 << " 1 " << x.x << ' ' << x.y << ' ' << x.z << '\n';
    }
    out << "\nVelocities\n\n";
    for (size_t i = 0; i < state.size(); ++i) {
        const Vec3<double>& v = state.velocity[i];
        out << i + 1 << ' ' << v.x << ' ' << v.y << ' ' << v.z << '\n';
    }
}

void writeInput(const fs::path& path, const Scene& scene, int64_t steps) {
    const double a = scene.species[0].radius;
    const SpeciesDef& s = scene.species[0];
    std::ofstream out(path);
    out.precision(17);
    out << "units lj\natom_style atomic\nboundary f f f\nread_data data.md\n"
        << "pair_style lj/cut " << scene.interaction.cutoff << "\n"
        << "pair_coeff 1 1 " << s.epsilon << ' ' << s.sigma << "\n"
        << "neighbor " << scene.interaction.skin << " bin\nneigh_modify every 1 delay 0 check yes\n"
        << "fix 1 all nve\n"
        << "fix 2 all wall/reflect";
    const char* axes[] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) out << ' ' << axes[k] << "lo " << a << ' ' << axes[k] << "hi " << scene.box.size[size_t(k)] - a;
    out << "\ntimestep " << scene.integrator.dt << "\nthermo " << steps << "\nrun " << steps << "\n";
}

}  // namespace

std::string findLammps(const std::string& request) {
    if (request == "off") return "";
    if (request != "auto") return request;
    for (const char* name : {"lmp", "lmp_serial", "lmp_mpi"}) {
        const std::string found = onPath(name);
        if (!found.empty()) return found;
    }
    return "";
}

std::optional<LammpsTiming> runLammps(const std::string& lmp, int ranks, const Scene& scene, const ParticleState& initial, int64_t steps) {
    const fs::path dir = fs::temp_directory_path() / ("corebox_lammps_" + std::to_string(getpid()) + "_" + std::to_string(initial.size()));
    fs::create_directories(dir);
    writeDataFile(dir / "data.md", scene, initial);
    writeInput(dir / "in.md", scene, steps);
    // Open MPI refuses root unless told; the single-copy mechanism fails in some containers.
    std::string command = "cd '" + dir.string() + "' && ";
    const std::string mpirun = onPath("mpirun");
    if (ranks > 1 && !mpirun.empty()) {
        command += "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + mpirun + " -np " + std::to_string(ranks) +
                   " --oversubscribe --mca btl_vader_single_copy_mechanism none ";
    }
    command += "'" + lmp + "' -in in.md -log log.lammps -screen none > lammps.out 2>&1";
    const int status = std::system(command.c_str());
    std::ifstream log(dir / "log.lammps");
    LammpsTiming timing;
    std::string line;
    while (std::getline(log, line)) {
        if (timing.version.empty() && line.rfind("LAMMPS (", 0) == 0) timing.version = line;
        double seconds = 0;
        int procs = 0;
        long long ran = 0;
        if (std::sscanf(line.c_str(), "Loop time of %lf on %d procs for %lld steps", &seconds, &procs, &ran) == 3 && ran > 0) {
            timing.secondsPerStep = seconds / double(ran);
            timing.steps = ran;
        }
    }
    if (status != 0 || timing.steps == 0) {
        std::fprintf(stderr, "[corebox] LAMMPS failed (exit status %d); its output is in %s\n", status, dir.string().c_str());
        return std::nullopt;
    }
    fs::remove_all(dir);
    return timing;
}

}  // namespace corebox
