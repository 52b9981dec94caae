// Output files: what is already at an output path is never damaged, and a regular file appears
// whole or not at all.
//
// Design note. What an output path names decides how it is written (OutputTarget):
// - a regular file, or nothing yet: written to "<target>.tmp-<pid>" beside the target and renamed
//   over it on commit(), so a failed or interrupted run leaves the old file as it was;
// - a symbolic link: followed (every level) to the file it names, which is then written as above
//   in the target's directory; the link itself stays a link;
// - anything else that can be opened for writing (a device such as /dev/null or /dev/full, a FIFO,
//   a terminal): streamed to directly; renaming over it would replace the node with a plain file;
// - a directory: refused when the run starts (checkOutput), not after the run.
// Rows of a long run are flushed as they are written (flush()), so a process killed with SIGKILL
// leaves "<target>.tmp-<pid>" holding a valid prefix of complete rows, while the final name keeps
// its old content; a normal end, an error and a first SIGINT/SIGTERM all commit or remove it.
// Every temporary is recorded in an async-signal-safe registry so that a signal handler can remove
// the ones still open (removeTemporaryFiles) before an immediate exit.
#pragma once

#include <fstream>
#include <string>
#include <vector>

namespace corebox {

enum class OutputKind { Missing, Regular, Stream, Directory };

struct OutputTarget {
    std::string path;       // as given
    std::string target;     // symbolic links followed; the file actually written or replaced
    OutputKind kind = OutputKind::Missing;
};

// What `path` names, symbolic links followed (a dangling link names its missing target).
OutputTarget inspectOutput(const std::string& path);

class AtomicFile {
public:
    // Throws InputError naming the path when it is a directory or the temporary (or, for a device
    // or FIFO, the node itself) cannot be opened: missing directory, no permission.
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ostream& stream() { return m_out; }
    const std::string& path() const { return m_path; }
    // Pushes what was written so far to the file; throws InputError (with the system's reason, e.g.
    // "No space left on device") when the write fails, so a full disk stops a run at once.
    void flush();
    // Flushes, checks the stream and renames into place (or closes the device); throws InputError
    // on failure.
    void commit();

private:
    std::string m_path;
    OutputTarget m_target;
    std::string m_tempPath;  // "" when streaming to a device or FIFO
    int m_registrySlot = -1;
    std::ofstream m_out;
    bool m_committed = false;
};

// Writes `bytes` to `path` by the rules above (temp-and-rename for regular files); throws
// InputError naming the path.
void writeOutputFile(const std::string& path, const std::string& bytes);

// Fails early (before a long run) when `path` could not be written: a directory, a missing or
// unwritable directory. Throws InputError naming the flag or key that gave the path.
void checkWritable(const std::string& path, const std::string& what);

// A file a run reads or writes, named by the flag or key that gave it.
struct NamedPath {
    std::string what;  // "--observables", "scene", "init.particles", ...
    std::string path;
};

// Refuses (InputError) an output that is one of the inputs, or the same file as another output:
// the same file after following links, or the same path not created yet. Devices such as
// /dev/null may be shared. Call after checkWritable, before anything is written.
void checkDistinctPaths(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs);

// Temporary files still open, for a signal handler: async-signal-safe (unlink only).
void removeTemporaryFiles();
// Records a temporary file made elsewhere (ffmpeg's video) for removeTemporaryFiles; returns the
// slot to release once the file is renamed or removed (-1: not recorded, a path too long).
int registerTemporaryFile(const std::string& path);
void releaseTemporaryFile(int slot);

}  // namespace corebox
