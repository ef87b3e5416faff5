// --video with ffmpeg (see video.h).
#include "video.h"

#include "external_program.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"

#include <vector>

namespace meso::app {

std::string ffmpegOrThrow(const std::filesystem::path& video) {
  const std::string ffmpeg = findOnPath("ffmpeg");
  if (ffmpeg.empty())
    throw Error(video.string() +
                ": --video: expected ffmpeg on the PATH (Debian: apt-get install ffmpeg)");
  return ffmpeg;
}

namespace {

// ffmpeg's image2 demuxer expands %d patterns: a literal % in the name is written %%.
std::string escapePercent(const std::string& s) {
  std::string out;
  for (char c : s) {
    out += c;
    if (c == '%') out += '%';
  }
  return out;
}

}  // namespace

void assembleVideo(const std::string& ffmpeg, const std::filesystem::path& video,
                   const std::filesystem::path& output, double fps, int firstFrame) {
  const std::filesystem::path tmp = temporarySibling(video);
  const std::string pattern =
      (output.parent_path() / (escapePercent(output.stem().string()) + "_%04d.png")).string();
  const int status =
      runProgram({ffmpeg, "-nostdin", "-loglevel", "error", "-y", "-framerate", std::to_string(fps),
                  "-start_number", std::to_string(firstFrame), "-i", pattern,
                  // yuv420p needs an even width and height: odd ones get a black last column/row.
                  "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p",
                  tmp.string()});
  std::error_code ec;
  if (status != 0) {
    std::filesystem::remove(tmp, ec);
    throw Error(video.string() + ": ffmpeg failed to assemble " + pattern +
                (status < 0 ? " (it did not start or was killed)"
                            : " (exit status " + std::to_string(status) + ")"));
  }
  std::filesystem::rename(tmp, video, ec);
  forgetTemporary(tmp);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error(video.string() + ": --video: cannot rename the complete video into place");
  }
}

}  // namespace meso::app
