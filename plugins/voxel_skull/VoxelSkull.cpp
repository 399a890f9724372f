#include "plugins/voxel_skull/VoxelSkull.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "framework/geometry/BackendBinding.h"
#include "framework/core/Lifecycle.h"
#include "framework/core/Strings.h"
#include "plugins/voxel_skull/MeshVoxelBackend.h"
#include "plugins/voxel_skull/Phantoms.h"
#include "framework/formats/volume/Resample.h"
#include "framework/formats/volume/VolumeReader.h"
#include "framework/formats/volume/VolumeWriter.h"

namespace trephine::voxel {

namespace {
// FNV-1a (64 bits) over the voxel codes taken 64 bits at a time (a
// fingerprint, not a standard digest: eight times fewer steps than bytewise),
// as 16 hexadecimal digits.
std::string checksum(const DensityVolume& volume) {
  uint64_t hash = 0xcbf29ce484222325ULL;
  const auto* bytes = reinterpret_cast<const unsigned char*>(volume.codes());
  const size_t size = volume.voxelCount() * sizeof(VoxelCode);
  size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    uint64_t word;
    std::memcpy(&word, bytes + i, 8);
    hash = (hash ^ word) * 0x100000001b3ULL;
  }
  for (; i < size; ++i) hash = (hash ^ bytes[i]) * 0x100000001b3ULL;
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}
}  // namespace


void VoxelSkull::init(InitContext& context) {
  // The collision back-end first: an unknown one is reported with any error of the volume.
  m_backend = createBackendAt<VoxelBackend>(context, d_backend, kTypeName);
  DensityVolume volume;
  formats::VolumeReadNotes notes;
  try {
    volume =
        d_file.isScheme() ? makePhantom(std::string(d_file.schemeBody())) : formats::readVolume(d_file.path(), &notes);
    if (d_voxelSize.value() > 0) volume = formats::resampleToVoxelSize(volume, d_voxelSize.value());
  } catch (const std::exception& e) {
    context.error(d_file, e.what());
    return;
  }
  for (const std::string& note : notes.notes) context.note(d_file, note);
  for (const std::string& warning : notes.warnings) context.warning(d_file, warning);
  if (!d_file.isScheme()) checkHounsfieldUnits(context, volume);
  if (!d_saveDrilled.value().empty()) {
    const std::string& name = d_saveDrilled.value();
    const bool meta = name.size() > 4 && (name.ends_with(".mha") || name.ends_with(".mhd"));
    if (!meta) context.error(d_saveDrilled, "expected a MetaImage file name ending in .mha or .mhd");
    if (!d_drill.value())
      context.error(d_saveDrilled, "nothing is drilled: set drill=\"true\" or leave saveDrilled empty");
  }
  m_forceRemoval = d_removal.is("force");
  checkRemovalFields(context);
  m_events = &context.events();
  if (m_backend && d_drill.value() && !m_forceRemoval && d_backend.value() != "native") {
    // Refused: the back-end is not bound (a mesh back-end would build its
    // surface, and start its threads, for nothing).
    context.error(d_backend,
                  "removal=\"thesis\" cuts the voxels the native back-end's contacts touch: use "
                  "backend=\"native\" or removal=\"force\"");
    m_bound = false;
    return;
  }
  try {
    setVolume(std::move(volume));
  } catch (const std::exception& e) {  // the back-end could not take the data
    context.error(d_backend, e.what());
    m_bound = false;
    return;
  }
  if (d_drill.value() && !m_forceRemoval) {
    // drillRate is in the volume's density units: a default meant for CT
    // units would wipe a volume normalised to [0, 1] in one frame. Say so.
    m_framesToDrillDensest =
        std::max(0.0, m_volume.maxDensity() - d_isovalue.value()) / (m_drillStep * m_volume.encoding().scale);
    if (m_framesToDrillDensest < 10)
      context.events().log(0, "drill_rate_fast", "the densest bone is cut through in under 10 frames", this,
                           m_framesToDrillDensest);
  }
}

MeshVoxelBackend* VoxelSkull::meshBackend() const {
  return m_bound ? dynamic_cast<MeshVoxelBackend*>(m_backend.get()) : nullptr;
}

std::optional<std::string> VoxelSkull::followSurfaceRebuild(const Component& rebuilder, ChannelHub& channels) {
  if (m_surfaceReady) return "another component already rebuilds the surface of " + path();
  m_surfaceReady = channels.subscribe<SurfaceCopy>(rebuilder, kSurfaceReadyChannel);
  m_surfaceInUse = &channels.publish<SurfaceCopy>(*this, kSurfaceInUseChannel);
  return std::nullopt;
}

void VoxelSkull::checkHounsfieldUnits(InitContext& context, const DensityVolume& volume) const {
  // A CT in Hounsfield units holds air near -1000 HU around the head. A scan
  // whose lowest value is far above that is in raw scanner units (or lost
  // its rescale), where soft tissue can read 500 to 1100: the isovalue, given
  // in HU, would take the scalp for bone.
  const double lowest = volume.minDensity(), highest = volume.maxDensity();
  if (!(lowest > kNoAirAbove)) return;
  char range[96];
  std::snprintf(range, sizeof range, "the volume's values run from %.6g to %.6g", lowest, highest);
  const std::string why = std::string(range) +
                          ", with no air near -1000: they do not look like Hounsfield units (raw scanner units, or "
                          "a file whose rescale was lost)";
  if (d_isovalue.isSet()) {
    context.note(d_isovalue, why + "; isovalue=" + formatDouble(d_isovalue.value()) +
                                 " is taken in the volume's own units");
    return;
  }
  context.warning(d_isovalue, why + ", so the default isovalue of " + formatDouble(d_isovalue.value()) +
                                  " HU may take soft tissue for bone. Give the scan in HU (a DICOM series is "
                                  "rescaled to them; for a raw volume, subtract its air value and add -1000), or set "
                                  "isovalue in the volume's own units (between its soft tissue and its bone)");
}

void VoxelSkull::checkRemovalFields(InitContext& context) {
  // A field the chosen law does not read would be silently ignored: refuse it.
  const BaseField* forceFields[] = {&d_cuttingEnergy, &d_referenceDensity, &d_hardnessExponent, &d_thrustThreshold,
                                    &d_maxCutSpeed};
  if (m_forceRemoval && d_drillRate.isSet())
    context.error(d_drillRate, "has no effect with removal=\"force\" (it is the rate of removal=\"thesis\")");
  if (!m_forceRemoval)
    for (const BaseField* field : forceFields)
      if (field->isSet()) context.error(*field, "has no effect with removal=\"thesis\" (force-driven removal only)");
  if (!d_drill.value())
    for (const BaseField* field : forceFields)
      if (field->isSet()) context.error(*field, "has no effect without drill=\"true\"");
  m_law.cuttingEnergy = 1000.0 * d_cuttingEnergy.value();  // J/mm^3 to N/mm^2 (mJ/mm^3)
  m_law.referenceDensity = d_referenceDensity.value();
  m_law.hardnessExponent = d_hardnessExponent.value();
  m_law.softestBone = d_isovalue.value();
  m_law.thrustThreshold = d_thrustThreshold.value();
  m_law.maxSpeed = d_maxCutSpeed.value();
}

void VoxelSkull::setVolume(DensityVolume volume) {
  m_volume = std::move(volume);
  m_initialChecksum = checksum(m_volume);
  const bool smooth = d_surface.is("smooth");
  m_grid = SolidGrid::of(m_volume, d_isovalue.value(), smooth);
  m_grid.buildOccupancy();  // smooth surface: the cells the point test must interpolate in
  m_algorithm1 = d_penetration.is("algorithm1") || (d_penetration.is("auto") && !smooth);
  if (m_backend) m_backend->bind({&m_volume, &m_grid, m_algorithm1});
  m_bound = m_backend != nullptr;
  // Drilling works on the stored codes: at least one code step per frame.
  m_drillStep =
      std::max<int32_t>(1, static_cast<int32_t>(std::lround(d_drillRate.value() / m_volume.encoding().scale)));
  m_pendingCuts.clear();  // a new volume: no cut pending
}

// The queries go to the collision back-end once it is bound to the data.
// Before that (the volume or the back-end failed to load, and the tools' init
// still announces their shells) there is nothing to hit.
ContactMemory VoxelSkull::reserveShell(std::span<const ShellPoint> shell) {
  ContactMemory memory;
  if (!m_bound) return memory;
  m_backend->reserveShell(shell);
  // At most the 8 voxel centres around each shell point (the smooth surface).
  if (d_drill.value() && !m_forceRemoval) memory.touched.reserve(8 * shell.size());
  m_pendingCuts.reserve(++m_reservedShells);
  return memory;
}
void VoxelSkull::describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
  if (m_bound) m_backend->describeTool(shell, solid);
}
SweepResult VoxelSkull::sweep(const SweepQuery& query) const {
  return m_bound ? askBackend(*this, d_backend, [&] { return m_backend->sweep(query); }) : SweepResult{};
}
bool VoxelSkull::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  return m_bound && askBackend(*this, d_backend, [&] { return m_backend->overlaps(X_WT, shell); });
}
std::optional<SurfaceHit> VoxelSkull::raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const {
  return m_bound ? askBackend(*this, d_backend, [&] { return m_backend->raycast(origin, direction, maxDistance); })
                 : std::nullopt;
}

std::optional<size_t> VoxelSkull::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  if (!m_bound) return std::nullopt;
  return askBackend(*this, d_backend, [&] { return m_backend->broadPhase(X_WT, shell); });
}

LevelSet VoxelSkull::exactShape() const {
  return d_file.isScheme() ? phantomShape(std::string(d_file.schemeBody())) : LevelSet{};
}

std::optional<ScanAsRead> VoxelSkull::scanAsRead() const {
  if (d_file.isScheme()) return std::nullopt;
  return ScanAsRead{std::make_shared<const DensityVolume>(formats::readVolume(d_file.path())), d_isovalue.value()};
}

Box3 VoxelSkull::bounds() const { return m_volume.bounds(); }

void VoxelSkull::declareOutputs(std::vector<OutputFile>& outputs) const {
  if (!d_saveDrilled.value().empty()) outputs.push_back({d_saveDrilled.value(), &d_saveDrilled});
}

void VoxelSkull::finish(FinishContext& context) {
  // The last frame's, which no next frame applied (events at their frame's time).
  applyPendingCuts(m_pendingCuts.empty() ? 0.0 : m_pendingCuts.back().t);
  if (d_saveDrilled.value().empty() || context.outputDirectory().empty()) return;
  if (!context.claimOutput(*this, d_saveDrilled.value())) return;
  const std::string& name = d_saveDrilled.value();
  try {
    formats::writeMetaImage(m_volume, context.outputDirectory() / name, /*compress=*/true);
  } catch (const std::exception& e) {
    context.error(*this, e.what());
  }
}

void VoxelSkull::reportCounters(std::vector<Counter>& counters) const {
  const auto& d = m_volume.dims();
  counters.push_back({"voxels", double(m_volume.voxelCount())});
  counters.push_back({"dims_x", double(d[0])});
  counters.push_back({"dims_y", double(d[1])});
  counters.push_back({"dims_z", double(d[2])});
  counters.push_back({"voxel_size_mm", m_volume.spacing().minCoeff()});  // the smallest side
  counters.push_back({"voxel_size_x_mm", m_volume.spacing().x()});
  counters.push_back({"voxel_size_y_mm", m_volume.spacing().y()});
  counters.push_back({"voxel_size_z_mm", m_volume.spacing().z()});
  counters.push_back({"bytes_per_voxel", double(sizeof(VoxelCode))});
  counters.push_back({"voxels_removed", double(m_voxelsRemoved)});
  if (d_drill.value() && !m_forceRemoval) counters.push_back({"frames_to_cut_densest_voxel", m_framesToDrillDensest});
  if (d_drill.value() && m_forceRemoval) {
    counters.push_back({"cut_frames", double(m_cutFrames)});
    counters.push_back({"max_cut_speed_mm_s", m_maxCutSpeed});
    // Volume of reference-density bone holding the density carved away.
    counters.push_back({"removed_bone_mm3", m_removedCodes * m_volume.encoding().scale * m_grid.spacing.prod() /
                                                d_referenceDensity.value()});
    counters.push_back({"breakthroughs", double(m_breakthroughs)});
  }
  if (m_backend) m_backend->reportCounters(counters);
}

void VoxelSkull::reportFacts(std::vector<Fact>& facts) const {
  facts.push_back({"backend", d_backend.value()});
  // What the volume held when loaded and holds now: equal unless something drilled it.
  facts.push_back({"volume_checksum_initial", m_initialChecksum});
  facts.push_back({"volume_checksum_final", checksum(m_volume)});
}

}  // namespace trephine::voxel
