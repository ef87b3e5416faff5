#include "bands_command.h"

#include "cli_options.h"
#include "command.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/relief/band_split.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace meso::app {
namespace {

// A table as a one-channel image: table row j (v grows upwards) is image row H - 1 - j, the
// inverse of how HeightTable reads images.
Image toImage(const HeightTable& t) {
  Image img(t.width(), t.heightTexels(), {"Y"});
  for (int j = 0; j < t.heightTexels(); ++j)
    for (int i = 0; i < t.width(); ++i) img.at(i, t.heightTexels() - 1 - j, 0) = t.at(i, j);
  return img;
}

CLI::App* addBandsOptions(CLI::App& cli, BandsCommandOptions& o) {
  CLI::App* b = cli.add_subcommand(
      "bands",
      "Split one height map into band-limited relief levels whose sum reproduces it (Becker & Max "
      "1993, 4.3); "
      "writes one EXR per band and prints each band's measured highest frequency");
  addOption(b, "height", o.height, "Height image (any format OpenImageIO reads)", CLI::ExistingFile)
      ->required();
  addOption(b, "-n,--levels", o.levels, "Number of bands", CLI::Range(1, 16))
      ->capture_default_str();
  addOption(b, "-o,--out-dir", o.outDir, "Folder for the band images")->capture_default_str();
  b->add_flag("--clamp", o.clamp, "The map does not tile (it is mirrored before filtering)");
  return b;
}

void runBands(const BandsCommandOptions& o, const RunContext& context) {
  if (o.levels < 1 || o.levels > 16)
    throw Error("--levels: expected 1..16, got " + std::to_string(o.levels));
  HeightTableOptions options;
  options.periodic = !o.clamp;
  options.memoryLimitBytes = context.memoryLimitBytes;
  const HeightTable table = loadHeightTable(o.height, options);
  try {
    checkBandLevels(table, o.levels);
  } catch (const Error& e) {
    throw Error(o.height.string() + ": --levels: " + e.what());
  }
  createOutputFolder(o.outDir, "-o");
  for (int k = 1; k <= o.levels; ++k)
    checkOutputFile(o.outDir / (o.height.stem().string() + "_band" + std::to_string(k) + ".exr"),
                    "-o");
  const std::vector<HeightBand> bands = splitBands(table, o.levels);
  std::printf("band,file,freq_cycles_per_tile,low_cut,high_cut,min,max\n");
  std::vector<double> sum(table.texels().size(), 0.0);
  for (size_t k = 0; k < bands.size(); ++k) {
    const HeightBand& b = bands[k];
    const std::filesystem::path file =
        o.outDir / (o.height.stem().string() + "_band" + std::to_string(k + 1) + ".exr");
    writeExr(file, toImage(b.table));
    const auto [lo, hi] = std::minmax_element(b.table.texels().begin(), b.table.texels().end());
    std::printf("%zu,%s,%g,%g,%g,%g,%g\n", k + 1, file.string().c_str(), b.freq, b.lowCut,
                b.highCut, *lo, *hi);
    for (size_t t = 0; t < sum.size(); ++t) sum[t] += b.table.texels()[t];
  }
  double worst = 0.0, range = 0.0;
  for (size_t t = 0; t < sum.size(); ++t) {
    worst = std::max(worst, std::abs(sum[t] - table.texels()[t]));
    range = std::max(range, static_cast<double>(std::abs(table.texels()[t])));
  }
  std::fprintf(stderr,
               "meso: %zu %s of %s (%dx%d); their sum reproduces it within %.3g (largest "
               "|height| %.3g)\n",
               bands.size(), bands.size() == 1 ? "band" : "bands", o.height.string().c_str(),
               table.width(), table.heightTexels(), worst, range);
  std::fprintf(stderr,
               "meso: in a scene, one level per band (coarsest first), amplitude in world units "
               "per unit of height:\n");
  for (size_t k = 0; k < bands.size(); ++k)
    std::fprintf(stderr,
                 "  [[materials.relief]]\n  height = \"%s\"\n  amplitude = 0.01\n  scale = 1.0\n",
                 (o.outDir / (o.height.stem().string() + "_band" + std::to_string(k + 1) + ".exr"))
                     .string()
                     .c_str());
}

}  // namespace

std::unique_ptr<Command> makeBandsCommand(CLI::App& cli) {
  return std::make_unique<OptionsCommand<BandsCommandOptions>>(cli, addBandsOptions, runBands);
}

}  // namespace meso::app
