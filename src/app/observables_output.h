// Where the observables rows of a run go: a file (atomic_file.h: a temporary renamed into place at
// the end, a device or FIFO streamed to) or stdout. Each row is written whole and flushed at once,
// so a long run shows progress in the file, a killed run leaves a valid prefix of complete rows,
// and a write error (a full disk, /dev/full, a closed pipe) stops the run with a message at the row
// that failed instead of a zero exit code and a truncated table.
//
// A run that recovers from blow-ups (blow_up_recovery.h) holds its rows back until the next recovery
// point: a recovery goes back to that point and discards the rows after it, so the table has one
// row per step, in order, with nothing written twice and nothing lost.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

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
    // Holding: rows wait in memory until release() (a recovery point) or commit().
    void hold() { m_holding = true; }
    void release();
    // A recovery went back to `step`: the held rows after it never happened.
    void discardAfter(int64_t step);
    // File: renamed into place (or closed); stdout: flushed. Throws InputError on a write error.
    void commit();
    // The file, or "stdout", for messages.
    std::string where() const;

private:
    void write(const std::string& text);

    std::unique_ptr<AtomicFile> m_file;
    std::string m_path;
    bool m_committed = false;
    bool m_holding = false;
    std::vector<std::pair<int64_t, std::string>> m_held;  // (step, formatted row)
};

}  // namespace corebox
