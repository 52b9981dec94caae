#include "atomic_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "errors.h"

namespace corebox {
namespace {

namespace fs = std::filesystem;

// The registry of open temporaries. A signal handler may only call async-signal-safe functions, so
// it cannot walk a std::vector another thread is resizing: fixed slots, claimed and released with
// lock-free atomics, each holding a NUL-terminated path. Enough slots for every PNG encoder thread
// plus the observables and state files of a run on a large host.
constexpr int kTempSlots = 512;
constexpr size_t kTempPathMax = 4096;
struct TempSlot {
    std::atomic<int> state{0};  // 0 free, 1 being filled, 2 holds a path
    char path[kTempPathMax];
};
TempSlot g_tempSlots[kTempSlots];
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the slots");

int registerTemporary(const std::string& path) {
    if (path.size() >= kTempPathMax) return -1;
    for (int i = 0; i < kTempSlots; ++i) {
        int expected = 0;
        if (g_tempSlots[i].state.compare_exchange_strong(expected, 1)) {
            std::memcpy(g_tempSlots[i].path, path.c_str(), path.size() + 1);
            g_tempSlots[i].state.store(2);
            return i;
        }
    }
    return -1;  // all slots taken: the file is still removed on every path but an immediate exit
}

void releaseTemporary(int slot) {
    if (slot >= 0) g_tempSlots[slot].state.store(0);
}

std::string reasonOf(int error) { return error != 0 ? std::strerror(error) : "write failed"; }

}  // namespace

int registerTemporaryFile(const std::string& path) { return registerTemporary(path); }
void releaseTemporaryFile(int slot) { releaseTemporary(slot); }

void removeTemporaryFiles() {
    for (TempSlot& slot : g_tempSlots) {
        if (slot.state.load() == 2) ::unlink(slot.path);
    }
}

OutputTarget inspectOutput(const std::string& path) {
    OutputTarget t{path, path, OutputKind::Missing};
    fs::path p(path);
    for (int depth = 0; depth < 40; ++depth) {
        struct stat st;
        if (::lstat(p.c_str(), &st) != 0) {
            t.target = p.string();
            return t;
        }
        if (S_ISLNK(st.st_mode)) {
            std::error_code ec;
            const fs::path link = fs::read_symlink(p, ec);
            if (ec) throw InputError("cannot follow the symbolic link '" + p.string() + "': " + ec.message());
            p = link.is_absolute() ? link : p.parent_path() / link;
            continue;
        }
        t.target = p.string();
        t.kind = S_ISREG(st.st_mode) ? OutputKind::Regular : S_ISDIR(st.st_mode) ? OutputKind::Directory : OutputKind::Stream;
        return t;
    }
    throw InputError("cannot write '" + path + "': too many levels of symbolic links");
}

AtomicFile::AtomicFile(std::string path) : m_path(std::move(path)), m_target(inspectOutput(m_path)) {
    if (m_target.kind == OutputKind::Directory) {
        throw InputError("cannot write '" + m_path + "': it is a directory; give a file name inside it");
    }
    if (m_target.kind == OutputKind::Stream) {
        m_out.open(m_target.target, std::ios::out | std::ios::binary);
        if (!m_out) throw InputError("cannot write '" + m_path + "': " + reasonOf(errno));
        return;
    }
    m_tempPath = m_target.target + ".tmp-" + std::to_string(::getpid());
    m_registrySlot = registerTemporary(m_tempPath);
    m_out.open(m_tempPath, std::ios::out | std::ios::trunc | std::ios::binary);
    if (!m_out) {
        const int error = errno;
        releaseTemporary(m_registrySlot);
        throw InputError("cannot write '" + m_path + "': " + reasonOf(error));
    }
    // A replaced file keeps its permissions (a file the user made private stays private).
    struct stat st;
    if (m_target.kind == OutputKind::Regular && ::stat(m_target.target.c_str(), &st) == 0) {
        ::chmod(m_tempPath.c_str(), st.st_mode & 07777);
    }
}

AtomicFile::~AtomicFile() {
    if (!m_committed) {
        m_out.close();
        if (!m_tempPath.empty()) std::remove(m_tempPath.c_str());
        releaseTemporary(m_registrySlot);
    }
}

void AtomicFile::flush() {
    errno = 0;
    m_out.flush();
    if (!m_out) throw InputError("cannot write '" + m_path + "': " + reasonOf(errno));
}

void AtomicFile::commit() {
    errno = 0;
    m_out.flush();
    bool good = bool(m_out);
    int error = errno;
    m_out.close();
    if (good && m_out.fail()) {
        good = false;
        error = errno;
    }
    if (good && !m_tempPath.empty() && std::rename(m_tempPath.c_str(), m_target.target.c_str()) != 0) {
        good = false;
        error = errno;
    }
    if (!m_tempPath.empty() && !good) std::remove(m_tempPath.c_str());
    releaseTemporary(m_registrySlot);
    m_committed = true;
    if (!good) throw InputError("cannot write '" + m_path + "': " + reasonOf(error));
}

void writeOutputFile(const std::string& path, const std::string& bytes) {
    AtomicFile file(path);
    file.stream().write(bytes.data(), std::streamsize(bytes.size()));
    file.commit();
}

void checkWritable(const std::string& path, const std::string& what) {
    const OutputTarget t = inspectOutput(path);
    if (t.kind == OutputKind::Directory) {
        throw InputError(what + ": '" + path + "' is a directory; give a file name inside it");
    }
    if (t.kind == OutputKind::Stream) {
        if (::access(t.target.c_str(), W_OK) != 0) throw InputError(what + ": cannot write '" + path + "': " + reasonOf(errno));
        return;
    }
    const std::string probe = t.target + ".tmp-probe-" + std::to_string(::getpid());
    std::FILE* f = std::fopen(probe.c_str(), "w");
    if (!f) throw InputError(what + ": cannot write '" + path + "': " + reasonOf(errno));
    std::fclose(f);
    std::remove(probe.c_str());
}

namespace {

// A file's identity: device and inode once it exists, else its absolute path with links followed
// as far as they exist (two outputs not created yet collide when these are equal).
struct FileIdentity {
    bool exists = false;
    bool shareable = false;  // a character device (/dev/null, a terminal): many writers are fine
    dev_t device = 0;
    ino_t inode = 0;
    std::string path;
};

FileIdentity identityOf(const std::string& path) {
    FileIdentity id;
    struct stat st;
    if (::stat(path.c_str(), &st) == 0) {
        id.exists = true;
        id.shareable = S_ISCHR(st.st_mode);
        id.device = st.st_dev;
        id.inode = st.st_ino;
        return id;
    }
    std::error_code ec;
    const fs::path target(inspectOutput(path).target);
    id.path = fs::weakly_canonical(fs::absolute(target, ec), ec).string();
    if (ec) id.path = fs::absolute(target).lexically_normal().string();
    return id;
}

bool sameFile(const FileIdentity& a, const FileIdentity& b) {
    if (a.exists != b.exists) return false;
    return a.exists ? a.device == b.device && a.inode == b.inode : a.path == b.path;
}

}  // namespace

void checkDistinctPaths(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs) {
    std::vector<FileIdentity> inputIds;
    for (const NamedPath& in : inputs) inputIds.push_back(in.path.empty() ? FileIdentity{} : identityOf(in.path));
    std::vector<FileIdentity> outputIds;
    for (size_t o = 0; o < outputs.size(); ++o) {
        const NamedPath& out = outputs[o];
        outputIds.push_back(out.path.empty() ? FileIdentity{} : identityOf(out.path));
        const FileIdentity& id = outputIds.back();
        if (out.path.empty() || id.shareable) continue;
        for (size_t i = 0; i < inputs.size(); ++i) {
            if (!inputs[i].path.empty() && sameFile(id, inputIds[i])) {
                throw InputError(out.what + ": '" + out.path + "' is this run's " + inputs[i].what + " ('" + inputs[i].path +
                                 "'); writing it would destroy the input: choose another file");
            }
        }
        for (size_t p = 0; p < o; ++p) {
            if (!outputs[p].path.empty() && sameFile(id, outputIds[p])) {
                throw InputError(out.what + " and " + outputs[p].what + " both name '" + out.path +
                                 "'; give each output its own file");
            }
        }
    }
}

}  // namespace corebox
