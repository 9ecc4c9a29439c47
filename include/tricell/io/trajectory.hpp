// Frames of a trajectory read one at a time, in constant memory.
//
// An extended XYZ file may hold any number of frames, one after the other (atom count, comment
// line, one line per atom; ASE's write("md.xyz", frames)). FrameReader reads the lines of one
// frame from the open file and hands them to the same parser read_structure() uses, so each
// frame is exactly what parse_structure() gives for that frame's text alone; memory is one frame,
// whatever the length of the file. Frames may differ in cell, periodicity and atom count. Blank
// lines after the last frame are ignored. The other formats (CIF, POSCAR) hold one structure:
// they are read whole and give one frame.
//
// Errors are ParseError "FILE:LINE: what is wrong (frame K)", LINE counted in the whole file and
// K the 0-based index of the frame being read.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "tricell/io/export.hpp"
#include "tricell/io/structure.hpp"

namespace tricell::io {

class TRICELL_IO_API FrameReader {
  public:
    /// Opens `path` (ParseError when it cannot be opened or its format is unknown; the format
    /// comes from the file name unless options.format says otherwise).
    explicit FrameReader(const std::string& path, const ReadOptions& options = {});
    ~FrameReader();
    FrameReader(FrameReader&&) noexcept;
    FrameReader& operator=(FrameReader&&) noexcept;
    FrameReader(const FrameReader&) = delete;
    FrameReader& operator=(const FrameReader&) = delete;

    /// Reads the next frame into `frame` and returns true; returns false (frame untouched) at
    /// the end. Throws ParseError for a malformed frame; after an error, next() throws again.
    bool next(Structure& frame);
    /// Frames returned so far.
    std::size_t frames_read() const;

  private:
    struct State;
    std::unique_ptr<State> state_;
};

} // namespace tricell::io
