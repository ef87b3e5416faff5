// `meso render`'s lines on stderr (render_report.h).
#include "render_report.h"

#include "meso/core/progress.h"

namespace meso::app {
namespace {

// "a", "a and b", "a, b and c".
std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i)
    out.append(i == 0 ? "" : i + 1 == names.size() ? " and " : ", ").append(names[i]);
  return out;
}

}  // namespace

std::string frameLine(int index, int count, int frame, int frames, double elapsed,
                      double framesSeconds) {
  const int done = index - 1;
  const std::string eta =
      done > 0 ? formatDuration(framesSeconds / done * (count - done)) : std::string("?");
  return "frame " + std::to_string(index) + " of " + std::to_string(count) + " (path frame " +
         std::to_string(frame) + " of " + std::to_string(frames) + "), elapsed " +
         formatDuration(elapsed) + ", ETA " + eta;
}

std::string writtenLine(const WrittenFiles& w) {
  std::vector<std::string> names;
  const size_t n = w.exrs.size();
  if (!w.animated || n == 1) {
    for (const std::filesystem::path& exr : w.exrs) {
      names.push_back(exr.string());
      names.push_back(pngBeside(exr).string());
    }
  } else if (n > 1) {
    names.push_back(std::to_string(n) + " frames (" + w.exrs.front().string() + " to " +
                    w.exrs.back().string() + ", each with its .png)");
  }
  if (!w.stats.empty()) names.push_back(w.stats.string());
  if (!w.video.empty()) names.push_back(w.video.string());
  return names.empty() ? "wrote no file" : "wrote " + listed(names);
}

}  // namespace meso::app
