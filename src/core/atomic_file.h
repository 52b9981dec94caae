// Output files appear whole or not at all: writes go to "<path>.tmp-<pid>" beside the target and
// are renamed over it on commit(). A writer destroyed without commit() (an error, an exception, a
// blow-up) removes its temporary, so no half-written file is ever left under the final name.
#pragma once

#include <fstream>
#include <string>

namespace corebox {

class AtomicFile {
public:
    // Throws InputError naming the path when the temporary cannot be created (missing directory,
    // no permission).
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ostream& stream() { return m_out; }
    const std::string& path() const { return m_path; }
    // Flushes, checks the stream and renames into place; throws InputError on failure.
    void commit();

private:
    std::string m_path;
    std::string m_tempPath;
    std::ofstream m_out;
    bool m_committed = false;
};

// Fails early (before a long run) when `path` could not be written: the directory is missing or
// not writable. Throws InputError naming the flag or key that gave the path.
void checkWritable(const std::string& path, const std::string& what);

}  // namespace corebox
