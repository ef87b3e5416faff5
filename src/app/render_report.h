// What `meso render` tells the user on stderr besides the library's per-frame progress bar: where
// a frame of a path stands in the run with an overall ETA, and a last line naming every file
// written.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace meso::app {

// The PNG preview written beside an EXR.
inline std::filesystem::path pngBeside(std::filesystem::path exr) {
  return exr.replace_extension(".png");
}

// "frame I of N (path frame F of FRAMES), elapsed m:ss, ETA m:ss": the I-th of the N frames this
// run renders; the ETA assumes the remaining frames take the mean time of those done (`?` before
// the first is done).
std::string frameLine(int index, int count, int frame, int frames, double elapsed,
                      double framesSeconds);

struct WrittenFiles {
  bool animated = false;
  std::vector<std::filesystem::path> exrs;  // each with its PNG beside it
  std::filesystem::path stats;              // empty: none
  std::filesystem::path video;              // empty: none
};

// "wrote A.exr, A.png and stats.json", or for a path "wrote 48 frames (X_0000.exr to X_0047.exr,
// each with its .png) and X.mp4"; "wrote no file" when every frame was already on disk.
std::string writtenLine(const WrittenFiles& written);

}  // namespace meso::app
