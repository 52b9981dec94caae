#include "atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "errors.h"

namespace corebox {

AtomicFile::AtomicFile(std::string path) : m_path(std::move(path)) {
    m_tempPath = m_path + ".tmp-" + std::to_string(::getpid());
    m_out.open(m_tempPath, std::ios::out | std::ios::trunc);
    if (!m_out) throw InputError("cannot write '" + m_path + "': " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
    if (!m_committed) {
        m_out.close();
        std::remove(m_tempPath.c_str());
    }
}

void AtomicFile::commit() {
    m_out.flush();
    const bool good = bool(m_out);
    m_out.close();
    if (!good || std::rename(m_tempPath.c_str(), m_path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        std::remove(m_tempPath.c_str());
        m_committed = true;
        throw InputError("cannot write '" + m_path + "': " + reason);
    }
    m_committed = true;
}

void checkWritable(const std::string& path, const std::string& what) {
    const std::string probe = path + ".tmp-probe-" + std::to_string(::getpid());
    std::FILE* f = std::fopen(probe.c_str(), "w");
    if (!f) throw InputError(what + ": cannot write '" + path + "': " + std::strerror(errno));
    std::fclose(f);
    std::remove(probe.c_str());
}

}  // namespace corebox
