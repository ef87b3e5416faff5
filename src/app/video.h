// --video: the frames' PNG previews assembled into an H.264 video by ffmpeg.
#pragma once

#include <filesystem>
#include <string>

namespace meso::app {

// ffmpeg's full path from $PATH, or meso::Error naming the option and how to install it.
std::string ffmpegOrThrow(const std::filesystem::path& video);

// Encodes OUTPUT-stem_%04d.png from firstFrame at fps into `video`, written under a temporary name
// and renamed; throws meso::Error if ffmpeg fails.
void assembleVideo(const std::string& ffmpeg, const std::filesystem::path& video,
                   const std::filesystem::path& output, double fps, int firstFrame);

}  // namespace meso::app
