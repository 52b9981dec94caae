#include "state_csv.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "atomic_file.h"
#include "errors.h"

namespace corebox {
namespace {

const char* kHeader = "id,species,x,y,z,vx,vy,vz";

std::string trimmed(const std::string& s) {
    size_t b = 0, e = s.size();
    while (b < e && (s[b] == ' ' || s[b] == '\t')) ++b;
    while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
    return s.substr(b, e - b);
}

}  // namespace

ParticleState readStateCsv(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError("cannot read '" + path + "': " + std::strerror(errno));
    return parseStateCsv(in, path);
}

ParticleState parseStateCsv(std::istream& in, const std::string& path) {
    std::string line;
    long lineNo = 0;
    if (!std::getline(in, line)) throw InputError(locatedMessage(path, 1, "", "empty file; expected the header " + std::string(kHeader)));
    ++lineNo;
    if (trimmed(line) != kHeader) {
        throw InputError(locatedMessage(path, 1, "header", "expected '" + std::string(kHeader) + "', found '" + trimmed(line) + "'"));
    }
    static const char* fields[] = {"id", "species", "x", "y", "z", "vx", "vy", "vz"};
    struct Row {
        long long id;
        long species;
        double values[6];
        long line;
    };
    std::vector<Row> rows;
    while (std::getline(in, line)) {
        ++lineNo;
        if (trimmed(line).empty()) continue;
        std::stringstream ss(line);
        std::string cell;
        Row row{};
        row.line = lineNo;
        for (int f = 0; f < 8; ++f) {
            if (!std::getline(ss, cell, ',')) {
                throw InputError(locatedMessage(path, lineNo, fields[f], "missing value (expected 8 columns)"));
            }
            cell = trimmed(cell);
            char* end = nullptr;
            errno = 0;
            if (f < 2) {
                const long long v = std::strtoll(cell.c_str(), &end, 10);
                if (cell.empty() || *end != '\0' || errno != 0) throw InputError(locatedMessage(path, lineNo, fields[f], "not an integer: '" + cell + "'"));
                if (f == 0) row.id = v;
                else row.species = long(v);
            } else {
                const double v = std::strtod(cell.c_str(), &end);
                if (cell.empty() || *end != '\0' || !std::isfinite(v)) {
                    throw InputError(locatedMessage(path, lineNo, fields[f], "not a finite number: '" + cell + "'"));
                }
                row.values[f - 2] = v;
            }
        }
        if (std::getline(ss, cell, ',')) throw InputError(locatedMessage(path, lineNo, "", "too many columns (expected 8)"));
        if (row.species < 0) throw InputError(locatedMessage(path, lineNo, "species", "must be >= 0"));
        rows.push_back(row);
    }
    ParticleState state;
    state.resize(rows.size());
    std::vector<char> seen(rows.size(), 0);
    for (const Row& row : rows) {
        if (row.id < 0 || row.id >= (long long)rows.size()) {
            throw InputError(locatedMessage(path, row.line, "id", "ids must be 0.." + std::to_string(rows.size() - 1) + ", found " + std::to_string(row.id)));
        }
        if (seen[size_t(row.id)]) throw InputError(locatedMessage(path, row.line, "id", "duplicate id " + std::to_string(row.id)));
        seen[size_t(row.id)] = 1;
        const size_t i = size_t(row.id);
        state.species[i] = int32_t(row.species);
        state.position[i] = {row.values[0], row.values[1], row.values[2]};
        state.velocity[i] = {row.values[3], row.values[4], row.values[5]};
    }
    return state;
}

void writeStateCsv(const std::string& path, const ParticleState& state) {
    AtomicFile file(path);
    std::ostream& out = file.stream();
    out << kHeader << '\n';
    char buffer[512];
    for (size_t i = 0; i < state.size(); ++i) {
        const Vec3<double>& x = state.position[i];
        const Vec3<double>& v = state.velocity[i];
        std::snprintf(buffer, sizeof buffer, "%zu,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", i, int(state.species[i]), x.x, x.y, x.z,
                      v.x, v.y, v.z);
        out << buffer;
    }
    file.commit();
}

}  // namespace corebox
