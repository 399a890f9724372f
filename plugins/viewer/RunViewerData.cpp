#include "plugins/viewer/RunViewerData.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "framework/core/AtomicFile.h"
#include "framework/core/FolderInput.h"
#include "framework/formats/encoding/Base64.h"
#include "framework/runtime/JsonWriter.h"
#include "framework/formats/vtk/VtkSurfaceReader.h"
#include "framework/data/CoarseIsoSurface.h"
#include "framework/data/IsoSurface.h"
#include "framework/data/VertexClustering.h"
#include "framework/formats/volume/VolumeReader.h"
#include "plugins/viewer/MeshColourRanges.h"
#include "plugins/viewer/ViewerAssets.h"
#include "plugins/viewer/ViewerVolume.h"

namespace trephine::viewer {

namespace fs = std::filesystem;

namespace {

// Plots keep at most this many points (each the largest of its rows): a
// plot is at most a few thousand pixels wide.
constexpr size_t kPlotPoints = 4000;

struct IndexEntry {
  double time = 0;  // s
  std::string file;  // relative to the run directory
};

struct PartState {
  std::string file;
  std::vector<std::pair<int, std::string>> changes;       // blocks: (block, file or "")
  std::vector<std::pair<int, std::string>> stillChanges;  // the same, finer: drawn when still
};

struct Part {
  std::string name, kind;
  std::vector<double> times;
  std::vector<PartState> states;
  fs::path folder;  // of its exporter, in the run
  std::map<std::string, double> ranges;  // mesh: the largest of each colour quantity (MeshColourRanges)
  std::string volume, removed;           // blocks: the packed skull volume's files (ViewerVolume), or none
  int volumeFactor = 1;
  size_t removedVoxels = 0;
};

// A skull's volume in the viewer: at most this many voxels (128^3; an
// eighth of a 0.5 mm head CT's), 4 MB before base64.
constexpr size_t kVolumeVoxels = size_t(1) << 21;

// What the viewer reads of a run must be the run's own: a regular file
// reached from its folder without a link (a link planted there to
// /etc/passwd, a device or a pipe is refused, never copied into the page).
fs::path inRun(const fs::path& run, const fs::path& relative) {
  try {
    return regularFileInside(run, relative);
  } catch (const FolderInputError& e) {
    throw ViewerDataError(e.what());
  }
}

// A file an index lists: the run's own, or missing.
void listedInRun(const fs::path& run, const fs::path& file, const fs::path& index) {
  try {
    regularFileInside(run, file);
  } catch (const FolderInputError& e) {
    if (e.missing()) throw ViewerDataError(index.string() + ": lists " + file.string() + ", which is missing");
    throw ViewerDataError(e.what());
  }
}

// A run's own VTK file is at most this big (a million-triangle skull block
// set or a 145k-tetrahedron brain frame are a few tens of MB).
constexpr size_t kMaxRunFileBytes = size_t(1) << 30;

std::string readBytes(const fs::path& file, size_t maxBytes = kMaxRunFileBytes) {
  try {
    return readRegularFile(file, maxBytes);
  } catch (const FolderInputError& e) {
    throw ViewerDataError(e.what());
  }
}

// The skull's volume files beside its exporter's frames, when there: the
// header, the data file it names, the isovalue and the removed voxels, each
// the run's own. The header must be what the exporter writes: a MetaImage
// (content first: it starts "ObjectType = Image") whose ElementDataFile, the
// first line with that key in any case as the reader takes it, is LOCAL or
// skull_density.zraw or .raw beside it; anything else (another format under
// that name, a data file elsewhere or through a link) is refused.
bool checkSkullFiles(const fs::path& run, const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(run / folder / "skull_density.mhd", ec))) return false;
  const fs::path headerFile = run / folder / "skull_density.mhd";
  const std::string header = readBytes(inRun(run, folder / "skull_density.mhd"), size_t(1) << 16);
  if (!header.starts_with("ObjectType = Image"))
    throw ViewerDataError(headerFile.string() + ": not the MetaImage header an exporter writes");
  std::optional<std::string> data;
  std::istringstream lines(header);
  for (std::string line; !data && std::getline(lines, line);) {
    const size_t equals = line.find('=');
    if (equals == std::string::npos) continue;
    std::string key = line.substr(0, equals), value = line.substr(equals + 1);
    const auto trim = [](std::string& s) {
      s.erase(0, s.find_first_not_of(" \t"));
      s.erase(s.find_last_not_of(" \t\r") + 1);
    };
    trim(key);
    trim(value);
    std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (key == "elementdatafile") data = value;
  }
  if (!data) throw ViewerDataError(headerFile.string() + ": no ElementDataFile");
  if (*data != "LOCAL") {
    if (*data != "skull_density.zraw" && *data != "skull_density.raw")
      throw ViewerDataError(headerFile.string() + ": its data file '" + *data +
                            "' is not the exporter's (skull_density.zraw or .raw beside it)");
    inRun(run, folder / *data);
  }
  for (const char* beside : {"skull_volume.json", "skull_removed.csv"})
    if (fs::exists(fs::symlink_status(run / folder / beside, ec))) inRun(run, folder / beside);
  return true;
}

void loadXml(tinyxml2::XMLDocument& document, const fs::path& file, const char* expected) {
  const std::string text = readBytes(file);
  if (document.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
    throw ViewerDataError(file.string() + ":" + std::to_string(document.ErrorLineNum()) + ": not XML (" +
                          document.ErrorStr() + ")");
  const tinyxml2::XMLElement* root = document.RootElement();
  if (!root || std::string(root->Name()) != "VTKFile" || !root->FirstChildElement(expected))
    throw ViewerDataError(file.string() + ": expected a VTKFile holding a " + expected);
}

// "vtk/brain_00012.vtu" -> "brain": the series a file belongs to.
std::string seriesName(const fs::path& file) {
  std::string stem = file.stem().string();
  const size_t underscore = stem.find_last_of('_');
  if (underscore != std::string::npos && underscore + 1 < stem.size() &&
      std::all_of(stem.begin() + underscore + 1, stem.end(), [](char c) { return c >= '0' && c <= '9'; }))
    stem.resize(underscore);
  return stem;
}

std::vector<IndexEntry> readCollection(const fs::path& pvd, const fs::path& run) {
  tinyxml2::XMLDocument document;
  loadXml(document, pvd, "Collection");
  std::vector<IndexEntry> entries;
  const auto* collection = document.RootElement()->FirstChildElement("Collection");
  for (const auto* e = collection->FirstChildElement("DataSet"); e; e = e->NextSiblingElement("DataSet")) {
    const char* file = e->Attribute("file");
    double time = NAN;
    if (!file || e->QueryDoubleAttribute("timestep", &time) != tinyxml2::XML_SUCCESS || !std::isfinite(time))
      throw ViewerDataError(pvd.string() + ":" + std::to_string(e->GetLineNum()) +
                            ": a DataSet needs a file and a finite timestep");
    const fs::path relative = (pvd.parent_path().lexically_relative(run) / file).lexically_normal();
    // The viewer reads the run's folder only: an index naming a file outside
    // it (an absolute path, "../") would copy that file into the viewer's data.
    if (fs::path(file).is_absolute() || relative.empty() || *relative.begin() == "..")
      throw ViewerDataError(pvd.string() + ":" + std::to_string(e->GetLineNum()) + ": '" + file +
                            "' is outside the run's folder (expected a path relative to it, inside it)");
    entries.push_back({time, relative.generic_string()});
  }
  return entries;
}

// The block files a .vtm lists, by block index, relative to the run.
std::map<int, std::string> readBlocks(const fs::path& vtm, const fs::path& run) {
  tinyxml2::XMLDocument document;
  loadXml(document, vtm, "vtkMultiBlockDataSet");
  std::map<int, std::string> blocks;
  const auto* set = document.RootElement()->FirstChildElement("vtkMultiBlockDataSet");
  for (const auto* e = set->FirstChildElement("DataSet"); e; e = e->NextSiblingElement("DataSet")) {
    int index = -1;
    const char* file = e->Attribute("file");
    if (!file || e->QueryIntAttribute("index", &index) != tinyxml2::XML_SUCCESS || index < 0)
      throw ViewerDataError(vtm.string() + ":" + std::to_string(e->GetLineNum()) +
                            ": a DataSet needs an index (0 or more) and a file");
    const fs::path relative = (vtm.parent_path().lexically_relative(run) / file).lexically_normal();
    if (*file && (fs::path(file).is_absolute() || relative.empty() || *relative.begin() == ".."))
      throw ViewerDataError(vtm.string() + ":" + std::to_string(e->GetLineNum()) + ": '" + file +
                            "' is outside the run's folder (expected a path relative to it, inside it)");
    blocks[index] = *file ? relative.generic_string() : "";
  }
  return blocks;
}

std::string kindOf(const std::string& file, const std::string& series) {
  const std::string extension = fs::path(file).extension().string();
  if (extension == ".vtu") return "mesh";
  if (extension == ".vtm") return "blocks";
  if (extension == ".vtp") return series == "tool" ? "tool" : "polydata";
  throw ViewerDataError(file + ": the viewer draws .vtu, .vtp and .vtm files, not " +
                        (extension.empty() ? std::string("a file without an extension") : "'" + extension + "'"));
}

struct Plots {
  std::vector<double> time, force, penetration;
};

// |F| and the penetration from trace.csv, at most kPlotPoints (the largest
// of each run of rows, so no peak is lost).
bool readPlots(const fs::path& trace, Plots& plots, double& end, ViewerDataSummary& summary) {
  std::ifstream in(trace);
  if (!in) return false;
  std::string line;
  if (!std::getline(in, line)) return false;
  std::vector<std::string> header;
  std::stringstream names(line);
  for (std::string name; std::getline(names, name, ',');) header.push_back(name);
  auto column = [&](const char* name) {
    auto at = std::find(header.begin(), header.end(), name);
    return at == header.end() ? -1 : static_cast<int>(at - header.begin());
  };
  const int t = column("t"), fx = column("force_x"), fy = column("force_y"), fz = column("force_z"),
            p = column("penetration");
  if (t < 0 || fx < 0 || fy < 0 || fz < 0 || p < 0) return false;
  Plots all;
  std::vector<double> row(header.size());
  size_t number = 1;
  // A row left out of the plots is said, by line: the first few, and the count.
  const auto leaveOut = [&](const std::string& why) {
    if (summary.rowsLeftOut++ < 5) summary.warnings.push_back(trace.filename().string() + ":" + std::to_string(number) + ": " + why);
  };
  while (std::getline(in, line)) {
    ++number;
    std::stringstream cells(line);
    size_t i = 0;
    std::string bad;
    for (std::string cell; std::getline(cells, cell, ',') && i < row.size(); ++i) {
      char* stop = nullptr;
      row[i] = std::strtod(cell.c_str(), &stop);
      const bool used = int(i) == t || int(i) == fx || int(i) == fy || int(i) == fz || int(i) == p;
      if (used && bad.empty() && (stop == cell.c_str() || *stop || !std::isfinite(row[i])))
        bad = header[i] + " is '" + cell + "', not a finite number";
    }
    if (i < row.size()) {
      leaveOut("a row of " + std::to_string(i) + " cells (the header has " + std::to_string(row.size()) +
               "): left out of the plots");
      continue;
    }
    if (!bad.empty()) {
      leaveOut(bad + ": the row is left out of the plots");
      continue;
    }
    all.time.push_back(row[t]);
    all.force.push_back(std::sqrt(row[fx] * row[fx] + row[fy] * row[fy] + row[fz] * row[fz]));
    all.penetration.push_back(row[p]);
  }
  if (all.time.empty()) return false;
  end = std::max(end, all.time.back());
  const size_t stride = (all.time.size() + kPlotPoints - 1) / kPlotPoints;
  for (size_t start = 0; start < all.time.size(); start += stride) {
    const size_t stop = std::min(start + stride, all.time.size());
    plots.time.push_back(all.time[start]);
    plots.force.push_back(*std::max_element(all.force.begin() + start, all.force.begin() + stop));
    plots.penetration.push_back(*std::max_element(all.penetration.begin() + start, all.penetration.begin() + stop));
  }
  return true;
}

void writeText(const OutputFolder& folder, const std::string& name, const std::string& text) {
  try {
    writeFileAtomically(folder, name, [&](std::ostream& out) { out << text; });
  } catch (const FileWriteError& e) {
    throw ViewerDataError(e.what());
  }
}

// The .tri bytes of a surface (see the header).
std::string triBytes(const TriangleMesh& surface) {
  std::string out = "TRI1";
  auto put = [&](const void* data, size_t size) { out.append(static_cast<const char*>(data), size); };
  const uint32_t counts[2] = {uint32_t(surface.vertices.size()), uint32_t(surface.triangles.size())};
  put(counts, sizeof counts);
  for (const Vec3& p : surface.vertices) {
    const float xyz[3] = {float(p.x()), float(p.y()), float(p.z())};
    put(xyz, sizeof xyz);
  }
  for (const auto& t : surface.triangles) {
    const uint32_t corners[3] = {uint32_t(t[0]), uint32_t(t[1]), uint32_t(t[2])};
    put(corners, sizeof corners);
  }
  return out;
}

// The skull's volume and its grid at the isovalue, from its exporter's folder.
struct SkullGrid {
  DensityVolume volume;
  VoxelGrid grid;
};

std::optional<SkullGrid> readSkullGrid(const fs::path& folder) {
  if (!fs::is_regular_file(folder / "skull_density.mhd")) return std::nullopt;
  const double isovalue = readSkullIsovalue(folder / "skull_volume.json");
  if (!std::isfinite(isovalue)) return std::nullopt;
  SkullGrid out;
  try {
    out.volume = formats::readVolume(folder / "skull_density.mhd");
  } catch (const std::exception& e) {
    throw ViewerDataError(e.what());
  }
  out.grid = VoxelGrid::of(out.volume, isovalue);
  return out;
}

using BlockChanges = std::vector<std::pair<int, std::string>>;  // (block, file or "")

// What simplifyBlocks made of a part at one level of detail.
struct BlockLevel {
  std::vector<BlockChanges> changes;  // per state
  size_t surfaceTriangles = 0, drawnTriangles = 0;
  double coarseCell = 0, drilledCell = 0;  // mm, 0: whole
  int pooledFactor = 0;  // the untouched bone from the volume pooled over f^3 voxels (0: clustered)
};

// A block part's surface at most `budget` triangles a state, as two
// pseudo-blocks: 0, the untouched blocks clustered (one file throughout),
// and 1, the blocks the drill changed, at that state (a file for each state
// whose drilled blocks differ). The files are named after the part and
// `level`; their bytes go to `generated`.
using SurfaceCache = std::map<std::string, TriangleMesh>;  // block file -> its surface, read once

BlockLevel simplifyBlocks(const Part& part, const fs::path& run, size_t budget, const std::string& level,
                          SurfaceCache& surfaces, std::map<std::string, std::string>& generated,
                          const VoxelGrid* volume) {
  BlockLevel out;
  auto surfaceOf = [&](const std::string& file) -> const TriangleMesh& {
    auto [at, added] = surfaces.try_emplace(file);
    if (added) {
      try {
        at->second = formats::readVtkPolyDataSurface(inRun(run, file));
      } catch (const formats::FileReadError& e) {
        throw ViewerDataError(e.what());
      }
    }
    return at->second;
  };
  // Each state's blocks; the blocks any later state changed.
  std::vector<std::map<int, std::string>> blocks;
  std::set<int> drilled;
  std::map<int, std::string> current;
  for (size_t s = 0; s < part.states.size(); ++s) {
    for (const auto& [block, file] : part.states[s].changes) {
      if (file.empty()) current.erase(block);
      else current[block] = file;
      if (s > 0) drilled.insert(block);
    }
    blocks.push_back(current);
  }
  auto drilledSurfaces = [&](size_t s) {
    std::vector<const TriangleMesh*> list;
    for (const auto& [block, file] : blocks[s])
      if (drilled.count(block)) list.push_back(&surfaceOf(file));
    return list;
  };
  auto count = [](const std::vector<const TriangleMesh*>& list) {
    size_t n = 0;
    for (const auto* s : list) n += s->triangles.size();
    return n;
  };
  // The drilled blocks: whole while they fit in half the budget.
  size_t drilledMost = 0, widest = 0;
  for (size_t s = 0; s < blocks.size(); ++s)
    if (const size_t n = count(drilledSurfaces(s)); n > drilledMost) drilledMost = n, widest = s;
  size_t drilledBudget = drilledMost;
  if (drilledMost > budget / 2)
    drilledBudget = simplifyToBudget(drilledSurfaces(widest), budget / 2, 0, &out.drilledCell).triangles.size();
  // The untouched blocks: the rest of the budget, never finer than the drilled ones.
  std::vector<const TriangleMesh*> untouched;
  for (const auto& [block, file] : blocks.empty() ? std::map<int, std::string>{} : blocks.front())
    if (!drilled.count(block)) untouched.push_back(&surfaceOf(file));
  out.surfaceTriangles = count(untouched) + drilledMost;
  const size_t untouchedBudget = std::max<size_t>(budget - std::min(budget, drilledBudget), budget / 4);
  TriangleMesh coarse;
  if (volume) {
    // The skull's volume pooled and isosurfaced, projected back onto the full
    // surface (CoarseIsoSurface), less the pieces of the drilled blocks: no
    // wall folds as vertex clustering folds it.
    const CoarseIsoSurface pooled =
        coarseIsoSurface(*volume, untouchedBudget, out.surfaceTriangles, BlockedIsoSurface::blocksPerAxisOf(*volume));
    for (size_t b = 0; b < pooled.pieces.size(); ++b) {
      if (drilled.count(int(b))) continue;
      const TriangleMesh& piece = pooled.pieces[b];
      const int32_t offset = int32_t(coarse.vertices.size());
      coarse.vertices.insert(coarse.vertices.end(), piece.vertices.begin(), piece.vertices.end());
      for (const auto& t : piece.triangles) coarse.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    }
    out.pooledFactor = pooled.factor;
    out.coarseCell = pooled.factor * volume->spacing.maxCoeff();
  } else {
    coarse = simplifyToBudget(untouched, untouchedBudget, out.drilledCell, &out.coarseCell);
  }
  const std::string coarseName = part.name + "/" + level + "_untouched.tri";
  generated[coarseName] = triBytes(coarse);
  size_t drawnMost = 0;
  std::string previous;
  out.changes.resize(part.states.size());
  for (size_t s = 0; s < part.states.size(); ++s) {
    BlockChanges& changes = out.changes[s];
    if (s == 0) changes.push_back({0, coarseName});
    std::string key;
    for (const auto& [block, file] : blocks[s])
      if (drilled.count(block)) key += file + ";";
    if (s > 0 && key == previous) continue;
    previous = key;
    const auto list = drilledSurfaces(s);
    TriangleMesh surface;
    if (out.drilledCell > 0) {
      VertexClustering clustering(out.drilledCell);
      for (const auto* piece : list) clustering.add(*piece);
      surface = clustering.result();
    } else {
      surface = simplifyToBudget(list, SIZE_MAX, 0);
    }
    drawnMost = std::max(drawnMost, surface.triangles.size());
    if (surface.triangles.empty()) {
      changes.push_back({1, ""});
      continue;
    }
    char name[48];
    std::snprintf(name, sizeof name, "_drilled_%05zu.tri", s);
    const std::string file = part.name + "/" + level + name;
    generated[file] = triBytes(surface);
    changes.push_back({1, file});
  }
  out.drawnTriangles = coarse.triangles.size() + drawnMost;
  return out;
}

}  // namespace

ViewerDataSummary writeViewerData(const fs::path& run, const OutputFolder& dataRoot, const std::string& folder,
                                  size_t index, size_t blockTriangles, uint64_t chunkBytes) {
  // Emptied first, and never through a link (OutputFolder).
  std::string plain = folder;
  while (plain.ends_with('/')) plain.pop_back();
  if (!plain.empty()) dataRoot.remove(plain);
  const OutputFolder data = plain.empty() ? dataRoot : dataRoot.subfolder(plain);
  if (plain.empty()) data.clear();
  std::vector<fs::path> indexes;
  for (const auto& entry : fs::directory_iterator(run))
    if (entry.path().extension() == ".pvd") indexes.push_back(inRun(run, entry.path().filename()));
  std::sort(indexes.begin(), indexes.end());
  if (indexes.empty())
    throw ViewerDataError(run.string() + ": no .pvd index (a scene writes one with a VtkExporter component)");

  // The parts, each file series of each index.
  std::vector<Part> parts;
  std::map<std::string, size_t> partOf;
  std::vector<double> times;
  for (const fs::path& pvd : indexes) {
    for (const IndexEntry& entry : readCollection(pvd, run)) {
      std::string name = seriesName(entry.file);
      if (indexes.size() > 1) name = pvd.stem().string() + "/" + name;
      auto [at, added] = partOf.try_emplace(name, parts.size());
      if (added) {
        Part part;
        part.name = name;
        part.kind = kindOf(entry.file, seriesName(entry.file));
        part.folder = run / pvd.stem();
        parts.push_back(std::move(part));
      }
      Part& part = parts[at->second];
      if (!part.times.empty() && entry.time < part.times.back())
        throw ViewerDataError(pvd.string() + ": " + entry.file + " goes back in time (" +
                              std::to_string(entry.time) + " s after " + std::to_string(part.times.back()) + " s)");
      listedInRun(run, entry.file, pvd);
      part.times.push_back(entry.time);
      part.states.push_back({entry.file, {}, {}});
      times.push_back(entry.time);
    }
  }
  // Blocks: each state as its changes against the one before.
  for (Part& part : parts) {
    if (part.kind != "blocks") continue;
    std::map<int, std::string> previous;
    for (PartState& state : part.states) {
      std::map<int, std::string> blocks = readBlocks(run / state.file, run);
      for (const auto& [block, file] : blocks) {
        if (!file.empty()) listedInRun(run, file, run / state.file);
        auto before = previous.find(block);
        if (before == previous.end() ? !file.empty() : before->second != file) state.changes.push_back({block, file});
      }
      for (const auto& [block, file] : previous)
        if (!file.empty() && !blocks.count(block)) state.changes.push_back({block, ""});
      previous = std::move(blocks);
    }
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  ViewerDataSummary summary;
  std::map<std::string, std::string> generated;  // file -> bytes, made here
  for (Part& part : parts) {
    if (part.kind != "blocks") continue;
    // Two levels: while playing or turning, and still (ten times finer).
    // The block files are read once for both levels.
    SurfaceCache surfaces;
    // The skull's volume as the run started, when its exporter wrote it.
    std::optional<SkullGrid> skullGrid;
    if (checkSkullFiles(run, part.folder.lexically_relative(run))) skullGrid = readSkullGrid(part.folder);
    const VoxelGrid* grid = skullGrid ? &skullGrid->grid : nullptr;
    const BlockLevel moving = simplifyBlocks(part, run, blockTriangles, "moving", surfaces, generated, grid);
    const BlockLevel still = simplifyBlocks(part, run, 10 * blockTriangles, "still", surfaces, generated, grid);
    summary.pooledFactor = moving.pooledFactor;
    for (size_t s = 0; s < part.states.size(); ++s) {
      part.states[s].changes = moving.changes[s];
      part.states[s].stillChanges = still.changes[s];
    }
    summary.surfaceTriangles += moving.surfaceTriangles;
    summary.drawnTriangles += moving.drawnTriangles;
    summary.stillTriangles += still.drawnTriangles;
    summary.coarseCell = std::max(summary.coarseCell, moving.coarseCell);
    summary.drilledCell = std::max(summary.drilledCell, moving.drilledCell);
  }

  // Colour ranges of the meshes; the skull's volume, packed.
  for (Part& part : parts) {
    if (part.kind == "mesh") {
      std::vector<fs::path> files;
      for (const PartState& state : part.states) files.push_back(run / state.file);
      part.ranges = meshColourRanges(files);
    } else if (part.kind == "blocks") {
      if (!checkSkullFiles(run, part.folder.lexically_relative(run))) continue;
      if (auto packed = packSkullVolume(part.folder, kVolumeVoxels)) {
        part.volume = part.name + "/volume.vol";
        part.removed = part.name + "/removed.rmv";
        generated[part.volume] = std::move(packed->density);
        generated[part.removed] = std::move(packed->removed);
        part.volumeFactor = packed->factor;
        part.removedVoxels = packed->removedVoxels;
      }
    }
  }

  // Frames: each part's latest state at each time.
  std::vector<std::vector<int>> frames(times.size(), std::vector<int>(parts.size(), -1));
  for (size_t p = 0; p < parts.size(); ++p) {
    size_t state = 0;
    int current = -1;
    for (size_t f = 0; f < times.size(); ++f) {
      while (state < parts[p].times.size() && parts[p].times[state] <= times[f]) current = static_cast<int>(state++);
      frames[f][p] = current;
    }
  }

  // Chunks, in the order the frames first need the files.
  std::map<std::string, size_t> chunkOf;
  std::ostringstream chunk;
  uint64_t chunkSize = 0;
  bool chunkEmpty = true;
  auto closeChunk = [&] {
    if (chunkEmpty) return;
    char name[32];
    std::snprintf(name, sizeof name, "chunk_%05zu.js", summary.chunks);
    writeText(data, name, chunk.str() + "});\n");
    ++summary.chunks;
    chunk.str("");
    chunkSize = 0;
    chunkEmpty = true;
  };
  auto pack = [&](const std::string& file) {
    if (file.empty() || chunkOf.count(file)) return;
    if (chunkSize >= chunkBytes) closeChunk();
    auto made = generated.find(file);
    const std::string bytes = made != generated.end() ? made->second : readBytes(run / file);
    if (chunkEmpty) chunk << "trephineChunk(" << index << ", " << summary.chunks << ", {\n";
    chunk << (chunkEmpty ? "" : ",\n") << '"' << JsonWriter::escape(file) << "\": \"" << formats::encodeBase64(bytes) << '"';
    chunkEmpty = false;
    chunkSize += bytes.size();
    summary.bytes += bytes.size();
    chunkOf[file] = summary.chunks;
  };
  // What playback needs first, then the still level of the blocks.
  for (const auto& frame : frames) {
    for (size_t p = 0; p < parts.size(); ++p) {
      if (frame[p] < 0) continue;
      const PartState& state = parts[p].states[frame[p]];
      if (parts[p].kind == "blocks")
        for (const auto& change : state.changes) pack(change.second);
      else
        pack(state.file);
    }
  }
  closeChunk();
  for (const auto& frame : frames)
    for (size_t p = 0; p < parts.size(); ++p)
      if (frame[p] >= 0 && parts[p].kind == "blocks")
        for (const auto& change : parts[p].states[frame[p]].stillChanges) pack(change.second);
  closeChunk();
  // Last, what only some views ask for: the skull's volume.
  for (const Part& part : parts) {
    pack(part.volume);
    pack(part.removed);
  }
  closeChunk();

  double end = times.empty() ? 0 : times.back();
  Plots plots;
  std::error_code ec;
  summary.plots =
      fs::exists(fs::symlink_status(run / "trace.csv", ec)) && readPlots(inRun(run, "trace.csv"), plots, end, summary);
  // Every other tool's trace (trace.PATH.csv: its renderer's path with dots
  // for slashes), plotted beside trace.csv's and named by that path.
  std::vector<std::pair<std::string, Plots>> toolPlots;
  for (const auto& entry : fs::directory_iterator(run, ec)) {
    const std::string name = entry.path().filename().string();
    const bool toolTrace = name.size() > 10 && name.rfind("trace.", 0) == 0 && name != "trace.csv" &&
                           name.compare(name.size() - 4, 4, ".csv") == 0;
    if (!toolTrace) continue;
    Plots tool;
    if (!readPlots(inRun(run, name), tool, end, summary)) continue;
    std::string path = "/" + name.substr(6, name.size() - 10);
    std::replace(path.begin(), path.end(), '.', '/');
    toolPlots.emplace_back(path, std::move(tool));
  }
  std::sort(toolPlots.begin(), toolPlots.end(), [](const auto& a, const auto& b) { return a.first < b.first; });

  std::ostringstream manifest;
  manifest << "window.trephineRuns = window.trephineRuns || [];\nwindow.trephineRuns[" << index << "] = ";
  JsonWriter json(manifest);
  json.beginObject();
  json.field("name", fs::absolute(run).lexically_normal().filename().string());
  json.field("source", run.string());
  json.field("folder", folder);
  json.field("end", end);
  json.key("parts").beginArray();
  for (const Part& part : parts) {
    json.beginObject().field("name", part.name).field("kind", part.kind);
    if (!part.ranges.empty()) {
      json.key("ranges").beginObject();
      for (const auto& [quantity, largest] : part.ranges) json.field(quantity, largest);
      json.endObject();
    }
    if (!part.volume.empty()) {
      json.key("volume").beginObject().field("density", part.volume).field("removed", part.removed);
      json.field("factor", static_cast<long long>(part.volumeFactor));
      json.field("removedVoxels", static_cast<unsigned long long>(part.removedVoxels)).endObject();
    }
    json.key("states").beginArray();
    for (const PartState& state : part.states) {
      if (part.kind != "blocks") {
        json.value(state.file);
        continue;
      }
      json.beginObject().field("file", state.file);
      for (auto [key, changes] : {std::pair{"changes", &state.changes}, {"still", &state.stillChanges}}) {
        json.key(key).beginArray();
        for (const auto& [block, file] : *changes) json.beginArray().value(block).value(file).endArray();
        json.endArray();
      }
      json.endObject();
    }
    json.endArray().endObject();
  }
  json.endArray();
  json.key("frames").beginArray();
  for (size_t f = 0; f < frames.size(); ++f) {
    json.beginObject().field("t", times[f]).key("states").beginArray();
    for (int state : frames[f]) json.value(state);
    json.endArray().endObject();
  }
  json.endArray();
  json.key("files").beginObject();
  for (const auto& [file, index] : chunkOf) json.field(file, static_cast<unsigned long long>(index));
  json.endObject();
  json.key("plots");
  if (summary.plots) {
    json.beginObject();
    for (auto [name, values] : {std::pair{"t", &plots.time}, {"force", &plots.force}, {"penetration", &plots.penetration}}) {
      json.key(name).beginArray();
      for (double v : *values) json.value(v);
      json.endArray();
    }
    json.endObject();
  } else {
    json.null();
  }
  json.key("toolPlots").beginArray();
  for (const auto& [path, tool] : toolPlots) {
    json.beginObject().field("name", path);
    for (auto [name, values] : {std::pair{"t", &tool.time}, {"force", &tool.force}, {"penetration", &tool.penetration}}) {
      json.key(name).beginArray();
      for (double v : *values) json.value(v);
      json.endArray();
    }
    json.endObject();
  }
  json.endArray();
  json.endObject();
  manifest << ";\n";
  // The run's summary (its events, for the plots and the time slider), as
  // text the viewer parses: JSON.parse, never run as script.
  if (fs::exists(fs::symlink_status(run / "summary.json", ec)))
    manifest << "window.trephineRuns[" << index << "].summary = \""
             << JsonWriter::escape(readBytes(inRun(run, "summary.json")))
             << "\";\n";
  writeText(data, "manifest.js", manifest.str());

  summary.frames = frames.size();
  summary.parts = parts.size();
  summary.files = chunkOf.size();
  summary.end = end;
  return summary;
}

namespace {

class BrowserRunViewer final : public RunViewer {
 public:
  std::filesystem::path assets() const override { return findViewerAssets(); }
  ViewerDataSummary writeViewerData(const std::filesystem::path& runDirectory, const OutputFolder& dataDirectory,
                                    const std::string& folder, size_t index,
                                    size_t blockTriangles) const override {
    return viewer::writeViewerData(runDirectory, dataDirectory, folder, index, blockTriangles);
  }
};

}  // namespace

std::shared_ptr<RunViewer> makeRunViewer() { return std::make_shared<BrowserRunViewer>(); }

}  // namespace trephine::viewer
