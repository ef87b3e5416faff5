// The meso command line: parses options and calls the library. Exit status 2 on bad input.
#include "render_command.h"

#include "meso/core/error.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

namespace {

void addRenderCommand(CLI::App& cli, meso::app::RenderCommandOptions& o) {
  CLI::App* render = cli.add_subcommand("render", "Render a scene to OpenEXR (with layers) and a PNG preview");
  render->add_option("scene", o.scene, "Scene file (TOML, see docs/scene-format.md)")->required();
  render->add_option("-o,--output", o.output, "Output .exr (default out/<scene name>.exr); the PNG preview is written beside it");
  render->add_option("--stats", o.statsFile, "Write timings, memory, counters and settings as JSON to this file");
  render->add_option("--spp", o.spp, "Samples per pixel (overrides camera.spp)")->check(CLI::Range(1, 65536));
  render->add_option("--threads", o.threads, "Worker threads, 0 = all cores (overrides render.threads)")->check(CLI::Range(0, 1024));
  render->add_option("--seed", o.seed, "Random seed (overrides render.seed)");
  render->add_option("--algorithm", o.algorithm, "auto|brdf|bump|redistribution|displacement (overrides render.algorithm)")
      ->check(CLI::IsMember({"auto", "brdf", "bump", "redistribution", "displacement"}));
  render->add_option("--tessellation-rate", o.tessellationRate, "Uniform Bfr tessellation rate per base-face edge")->check(CLI::Range(1, 64));
  render->add_option("--width", o.width, "Image width in pixels (overrides camera.resolution)")->check(CLI::Range(1, 16384));
  render->add_option("--height", o.height, "Image height in pixels (overrides camera.resolution)")->check(CLI::Range(1, 16384));
  render->add_flag("--false-colour,--false-color", o.falseColour,
                   "Beauty in the algorithm colours (brdf yellow, bump green, redistribution blue, displacement red, synthesis magenta)");
  render->add_option("--frames", o.frames, "Frames A:B (inclusive) of the scene's [path]; default all");
  render->add_option("--shard", o.shard, "i/n: render only the frames f with f % n == i (for farms)");
  render->add_flag("--overwrite", o.overwrite, "Re-render frames whose EXR and PNG already exist");
  render->add_option("--video", o.video, "Assemble the frames' PNGs into this video with ffmpeg (must be on the PATH)");
  render->add_flag("-q,--quiet", o.quiet, "No progress bar and no summary");
  render->callback([&o] { meso::app::runRender(o); });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"meso: bumpy surfaces at every distance (Becker & Max 1993)"};
  cli.require_subcommand(1);
  meso::app::RenderCommandOptions renderOptions;
  addRenderCommand(cli, renderOptions);
  meso::app::installInterruptHandler();
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = cli.exit(e);
    return status == 0 ? 0 : 2;
  } catch (const meso::app::RenderInterrupted&) {
    std::fprintf(stderr, "meso: interrupted; complete frames are kept, nothing partial was written\n");
    return 130;
  } catch (const meso::Error& e) {
    std::fprintf(stderr, "meso: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "meso: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
