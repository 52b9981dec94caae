#include "checkpoint.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "atomic_file.h"
#include "errors.h"

namespace corebox {
namespace {

constexpr char kMagic[] = "corebox checkpoint\n";
// 4: the contact impulses' colours after them; 3: the contact relaxation's warm-start impulses after the
// accelerations; 2: the cached accelerations after the particles; 1: none of these. All four are read.
constexpr uint32_t kVersion = 4;
static_assert(sizeof(ContactWarmStart) == 2 * sizeof(int64_t) + sizeof(double), "warm-start impulses are written as raw records");
constexpr uint32_t kByteOrderProbe = 0x01020304;
static_assert(sizeof(Vec3<double>) == 3 * sizeof(double), "positions and velocities are written as raw doubles");

class Writer {
public:
    template <class T>
    void put(const T& value) {
        static_assert(std::is_trivially_copyable<T>::value, "raw bytes only");
        m_bytes.append(reinterpret_cast<const char*>(&value), sizeof(T));
    }
    void putString(const std::string& s) {
        put(uint64_t(s.size()));
        m_bytes += s;
    }
    template <class T>
    void putArray(const std::vector<T>& values) {
        if (!values.empty()) m_bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    }
    std::string& bytes() { return m_bytes; }

private:
    std::string m_bytes;
};

class Reader {
public:
    Reader(const std::string& bytes, size_t begin, size_t end, std::string path)
        : m_bytes(bytes), m_at(begin), m_end(end), m_path(std::move(path)) {}

    template <class T>
    T get(const char* what) {
        T value;
        take(&value, sizeof(T), what);
        return value;
    }
    std::string getString(const char* what) {
        const uint64_t size = get<uint64_t>(what);
        if (size > m_end - m_at) fail(std::string(what) + " runs past the end of the file");
        std::string s = m_bytes.substr(m_at, size_t(size));
        m_at += size_t(size);
        return s;
    }
    template <class T>
    void getArray(std::vector<T>& values, const char* what) {
        if (!values.empty()) take(values.data(), values.size() * sizeof(T), what);
    }
    size_t remaining() const { return m_end - m_at; }
    [[noreturn]] void fail(const std::string& why) const { throw InputError("checkpoint '" + m_path + "': " + why); }

private:
    void take(void* out, size_t n, const char* what) {
        if (n > m_end - m_at) fail(std::string("truncated (ends inside ") + what + ")");
        std::memcpy(out, m_bytes.data() + m_at, n);
        m_at += n;
    }

    const std::string& m_bytes;
    size_t m_at;
    size_t m_end;
    std::string m_path;
};

}  // namespace

uint64_t checkpointChecksum(const std::string& bytes) {
    uint64_t hash = 1469598103934665603ull;
    for (unsigned char c : bytes) {
        hash ^= c;
        hash *= 1099511628211ull;
    }
    return hash;
}

void writeCheckpoint(const std::string& path, const SimulationCheckpoint& c) {
    if (!c.contactColours.empty() && c.contactColours.size() != c.contactImpulses.size())
        throw std::invalid_argument("checkpoint '" + path + "': " + std::to_string(c.contactColours.size()) +
                                    " contact colours for " + std::to_string(c.contactImpulses.size()) +
                                    " contact impulses");
    Writer w;
    w.bytes().append(kMagic, sizeof(kMagic) - 1);
    w.put(kVersion);
    w.put(kByteOrderProbe);
    w.put(uint32_t(sizeof(double)));
    w.putString(c.sceneToml);
    w.put(c.step);
    for (double v : {c.time, c.dissipated, c.thermostatEnergy, c.parameterWork, c.conserved0, c.energyScale, c.lastKinetic, c.dtNext,
                     c.pressureTime, c.pressureKineticTime})
        w.put(v);
    for (int64_t v : {c.pairCollisions, c.wallCollisions, c.roundCapHits}) w.put(v);
    w.put(c.pressureImpulses);
    w.put(uint64_t(c.state.size()));
    w.putArray(c.state.position);
    w.putArray(c.state.velocity);
    w.putArray(c.state.species);
    w.put(uint64_t(c.accelerations.size()));
    w.putArray(c.accelerations);
    w.put(uint64_t(c.contactImpulses.size()));
    w.putArray(c.contactImpulses);
    w.put(uint64_t(c.contactColours.size()));
    w.putArray(c.contactColours);
    w.put(checkpointChecksum(w.bytes()));
    std::error_code ec;
    if (std::filesystem::is_regular_file(path, ec)) {
        std::filesystem::rename(path, path + ".prev", ec);
        if (ec) throw InputError("checkpoint '" + path + "': cannot keep the previous one as " + path + ".prev: " + ec.message());
    }
    writeOutputFile(path, w.bytes());
}

SimulationCheckpoint readCheckpoint(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read checkpoint '" + path + "': " + std::strerror(errno));
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t magic = sizeof(kMagic) - 1;
    if (bytes.size() < magic || bytes.compare(0, magic, kMagic) != 0)
        throw InputError("checkpoint '" + path + "': not a corebox checkpoint (those are written by --checkpoint)");
    const size_t header = magic + 3 * sizeof(uint32_t);
    if (bytes.size() < header + sizeof(uint64_t)) throw InputError("checkpoint '" + path + "': truncated");
    const size_t end = bytes.size() - sizeof(uint64_t);
    Reader r(bytes, magic, end, path);
    const uint32_t version = r.get<uint32_t>("the version");
    if (version < 1 || version > kVersion)
        r.fail("format version " + std::to_string(version) + "; this corebox reads version " + std::to_string(kVersion));
    if (r.get<uint32_t>("the byte-order probe") != kByteOrderProbe || r.get<uint32_t>("the size probe") != sizeof(double))
        r.fail("written on a machine with another byte order or number format");
    uint64_t stored = 0;
    std::memcpy(&stored, bytes.data() + end, sizeof(stored));
    if (checkpointChecksum(bytes.substr(0, end)) != stored)
        r.fail("truncated or damaged (its checksum does not match)");

    SimulationCheckpoint c;
    c.sceneToml = r.getString("the scene");
    c.step = r.get<int64_t>("the step");
    for (double* v : {&c.time, &c.dissipated, &c.thermostatEnergy, &c.parameterWork, &c.conserved0, &c.energyScale, &c.lastKinetic,
                      &c.dtNext, &c.pressureTime, &c.pressureKineticTime})
        *v = r.get<double>("the energy bookkeeping");
    for (int64_t* v : {&c.pairCollisions, &c.wallCollisions, &c.roundCapHits}) *v = r.get<int64_t>("the counters");
    c.pressureImpulses = r.get<ImpulseSums>("the pressure window");
    const uint64_t n = r.get<uint64_t>("the particle count");
    const size_t perParticle = 2 * sizeof(Vec3<double>) + sizeof(int32_t);
    if (n > r.remaining() / perParticle || (version == 1 && r.remaining() != n * perParticle))
        r.fail("holds " + std::to_string(r.remaining()) + " bytes of particles, not the " + std::to_string(n) + " it announces");
    c.state.resize(size_t(n));
    r.getArray(c.state.position, "the positions");
    r.getArray(c.state.velocity, "the velocities");
    r.getArray(c.state.species, "the species");
    if (version >= 2) {
        const uint64_t cached = r.get<uint64_t>("the accelerations' count");
        const size_t following = version >= 3 ? sizeof(uint64_t) : 0;  // the impulses' count
        if ((cached != 0 && cached != n) || r.remaining() < following || (r.remaining() - following) / sizeof(Vec3<double>) < cached ||
            (version == 2 && r.remaining() != cached * sizeof(Vec3<double>)))
            r.fail("holds " + std::to_string(r.remaining()) + " bytes of accelerations, not the " + std::to_string(cached) + " it announces");
        c.accelerations.resize(size_t(cached));
        r.getArray(c.accelerations, "the accelerations");
    }
    if (version >= 3) {
        const uint64_t impulses = r.get<uint64_t>("the contact impulses' count");
        const size_t following = version >= 4 ? sizeof(uint64_t) : 0;  // the colours' count
        if (r.remaining() < following || (r.remaining() - following) / sizeof(ContactWarmStart) < impulses ||
            (version == 3 && r.remaining() != impulses * sizeof(ContactWarmStart)))
            r.fail("holds " + std::to_string(r.remaining()) + " bytes of contact impulses, not the " + std::to_string(impulses) +
                   " it announces");
        c.contactImpulses.resize(size_t(impulses));
        r.getArray(c.contactImpulses, "the contact impulses");
    }
    if (version >= 4) {
        const uint64_t colours = r.get<uint64_t>("the contact colours' count");
        if (colours != 0 && colours != c.contactImpulses.size())
            r.fail("announces " + std::to_string(colours) + " contact colours for " +
                   std::to_string(c.contactImpulses.size()) + " contact impulses");
        if (r.remaining() != colours)
            r.fail("holds " + std::to_string(r.remaining()) + " bytes of contact colours, not the " +
                   std::to_string(colours) + " it announces");
        c.contactColours.resize(size_t(colours));
        r.getArray(c.contactColours, "the contact colours");
    }
    return c;
}

}  // namespace corebox
