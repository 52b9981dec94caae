// Where the observables rows of a run go: a file (atomic_file.h: a temporary renamed into place at
// the end, a device or FIFO streamed to) or stdout. Each row is written whole and flushed at once,
// so a long run shows progress in the file, a killed run leaves a valid prefix of complete rows,
// and a write error (a full disk, /dev/full, a closed pipe) stops the run with a message at the row
// that failed instead of a zero exit code and a truncated table.
#pragma once

#include <memory>
#include <string>

#include "atomic_file.h"
#include "observables.h"
#include "scene.h"

namespace corebox {

class ObservablesOutput {
public:
    // path "" : stdout. Throws InputError when the file cannot be opened.
    explicit ObservablesOutput(const std::string& path);

    void header(const Scene& scene);
    void row(const ObservablesRow& row);
    // File: renamed into place (or closed); stdout: flushed. Throws InputError on a write error.
    void commit();
    // The file, or "stdout", for messages.
    std::string where() const;

private:
    void write(const std::string& text);

    std::unique_ptr<AtomicFile> m_file;
    std::string m_path;
    bool m_committed = false;
};

}  // namespace corebox
