#include "observables_output.h"

#include <cerrno>
#include <cstring>
#include <iostream>
#include <sstream>

#include "errors.h"

namespace corebox {

ObservablesOutput::ObservablesOutput(const std::string& path) : m_path(path) {
    if (!path.empty()) m_file = std::make_unique<AtomicFile>(path);
}

void ObservablesOutput::header(const Scene& scene) { write(observablesHeader(scene) + "\n"); }

void ObservablesOutput::row(const ObservablesRow& row) {
    // Formatted first, then written and flushed in one piece: the file never ends inside a row.
    std::ostringstream text;
    writeObservablesRow(text, row);
    if (m_holding) {
        m_held.emplace_back(row.step, text.str());
        return;
    }
    write(text.str());
}

void ObservablesOutput::release() {
    std::string text;
    for (const auto& [step, line] : m_held) text += line;
    m_held.clear();
    if (!text.empty()) write(text);
}

void ObservablesOutput::discardAfter(int64_t step) {
    while (!m_held.empty() && m_held.back().first > step) m_held.pop_back();
}

void ObservablesOutput::write(const std::string& text) {
    if (m_file) {
        m_file->stream() << text;
        m_file->flush();
        return;
    }
    errno = 0;
    std::cout << text;
    std::cout.flush();
    if (!std::cout) {
        throw InputError(std::string("cannot write the observables to stdout: ") + (errno ? std::strerror(errno) : "write failed") +
                         " (was the reading end of a pipe closed? use --observables FILE)");
    }
}

void ObservablesOutput::commit() {
    if (m_committed) return;  // an instability after a commit, a second finish()
    m_committed = true;
    release();
    if (m_file) {
        m_file->commit();
        m_file.reset();
    } else {
        write("");
    }
}

std::string ObservablesOutput::where() const { return m_path.empty() ? "stdout" : m_path; }

}  // namespace corebox
