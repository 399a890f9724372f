// All CGAL Mesh_3 code of the project: the implicit solids and the labelled
// images (framework/meshing/TetMeshing.h) share one domain type, so
// Mesh_3's templates are compiled once.
#include <CGAL/Image_3.h>
#include <CGAL/ImageIO.h>
#include <CGAL/Mesh_3/initialize_triangulation_from_labeled_image.h>

#include "plugins/meshing/CgalMesher.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Random.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <iostream>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

namespace trephine::meshing {

namespace {

// Bisection tolerance of surface points, relative to the bounding sphere.
constexpr double kRelativeErrorBound = 1e-6;
// Fixed seed of the initial surface points: the mesh depends only on the target.
constexpr unsigned int kSeed = 20240601;

constexpr int kMinTargetTets = 100;
constexpr int kMaxTargetTets = 2000000;
// Refinement runs at most, and the relative deviation of the refined count
// from its target that ends them early.
constexpr int kMaxRuns = 4;
constexpr double kAim = 0.025;
// Smallest dihedral angle that sliver perturbation aims at (deg).
constexpr double kPerturbBound = 10.0;
// Fraction of the refined mesh's tets left after sliver removal (measured over
// 1.5k to 50k tets: 0.952 to 0.960).
constexpr double kSliverRemovalRetention = 0.957;

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Domain = CGAL::Labeled_mesh_domain_3<Kernel>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;

// What is meshed: a domain made afresh for each run from its own seeded
// random generator (its initial surface points), so every run starts from
// the same seed whatever ran before; and the count model's terms.
struct MeshingProblem {
  std::function<Domain(CGAL::Random&)> makeDomain;
  // The refined count at cell size s is about volumeTerm / s^3 + surfaceTerm / s^2.
  double volumeTerm = 1, surfaceTerm = 0;
  double leastFacetDistance = 0;  // mm
  Vec3 offset = Vec3::Zero();     // mm, added to every node (image domains mesh in image coordinates)
  // Puts the first points into the complex (each connected region of an
  // image seeded, so small ones are not missed); else Mesh_3's own
  // initialisation (random rays from the centre).
  std::function<void(Complex&, const Domain&, const Criteria&)> initialize;
  bool labelled = false;          // tetrahedra keep their subdomain index; else all 1
  std::function<double(const Vec3&)> sizeFactor;  // optional, in (0, 1]: finer where it is smaller
};

// A size that varies over the domain (CGAL's MeshDomainField_3): `base`
// (mm) times the problem's factor at the point.
struct ScaledSize {
  using FT = Kernel::FT;
  using Point_3 = Point;
  double base = 1;
  std::function<double(const Vec3&)> factor;
  template <class Index>
  FT operator()(const Point& p, const int, const Index&) const {
    return base * std::clamp(factor(Vec3(p.x(), p.y(), p.z())), 0.05, 1.0);
  }
};

struct SeededDomain {
  CGAL::Random random{kSeed};
  Domain domain;
  explicit SeededDomain(const MeshingProblem& problem) : domain(problem.makeDomain(random)) {}
};

MeshingProblem implicitProblem(const ImplicitSolid& solid) {
  MeshingProblem problem;
  const Kernel::Sphere_3 bounds(Point(solid.centre.x(), solid.centre.y(), solid.centre.z()),
                                solid.boundingRadius * solid.boundingRadius);
  if (solid.region) {
    // Regions: the label of each point (0 outside the solid); the surfaces
    // are found between labels by bisection, so they conform to every region.
    problem.makeDomain = [solid, bounds](CGAL::Random& random) {
      const std::function<int(const Point&)> labelOf = [distance = solid.distance,
                                                         region = solid.region](const Point& p) {
        const Vec3 q(p.x(), p.y(), p.z());
        return distance(q) < 0 ? std::max(1, int(region(q))) : 0;
      };
      return Domain(labelOf, bounds, kRelativeErrorBound, CGAL::Null_subdomain_index(), &random);
    };
    problem.labelled = true;
  } else {
    problem.makeDomain = [solid, bounds](CGAL::Random& random) {
      return Domain::create_implicit_mesh_domain(
          [distance = solid.distance](const Point& p) { return distance(Vec3(p.x(), p.y(), p.z())); }, bounds,
          CGAL::parameters::relative_error_bound = kRelativeErrorBound, CGAL::parameters::p_rng = &random);
    };
  }
  problem.volumeTerm = solid.volumeTerm;
  problem.surfaceTerm = solid.surfaceTerm;
  problem.leastFacetDistance = solid.leastFacetDistance;
  problem.sizeFactor = solid.sizeFactor;
  return problem;
}

// Delaunay refinement only (no perturbation or exudation), with cells and
// surface facets of circumradius at most `size` (mm).
Complex refine(const MeshingProblem& problem, double size) {
  namespace params = CGAL::parameters;
  const SeededDomain seeded(problem);
  // Facet distance follows the size so that the tet count keeps scaling as
  // size^-3 (a fixed one would set a floor of surface tets); a tenth of the
  // size keeps the brain phantom's fissure open down to 3500 tets.
  const double facetDistance = std::max(problem.leastFacetDistance, 0.1 * size);
  const Criteria criteria =
      problem.sizeFactor
          ? Criteria(params::facet_angle = 25.0, params::facet_size = ScaledSize{size, problem.sizeFactor},
                     params::facet_distance = ScaledSize{facetDistance, problem.sizeFactor},
                     params::cell_radius_edge_ratio = 3.0, params::cell_size = ScaledSize{size, problem.sizeFactor})
          : Criteria(params::facet_angle = 25.0, params::facet_size = size, params::facet_distance = facetDistance,
                     params::cell_radius_edge_ratio = 3.0, params::cell_size = size);
  if (!problem.initialize)
    return CGAL::make_mesh_3<Complex>(seeded.domain, criteria, params::no_perturb(), params::no_exude());
  Complex complex;
  problem.initialize(complex, seeded.domain, criteria);
  CGAL::refine_mesh_3(complex, seeded.domain, criteria, params::no_perturb(), params::no_exude());
  return complex;
}

// Sliver removal: raises the smallest dihedral angle from under 1 deg to 10 deg.
// Time limit 0 is none: the default (the refinement's duration) would make the
// result depend on the machine's speed. Perturbation stops at kPerturbBound
// (without a bound it takes up to 5 s to gain 2 deg more); exudation then runs
// to the end (bound 0), flipping about 4% of the tets away.
void removeSlivers(const MeshingProblem& problem, Complex& complex) {
  namespace params = CGAL::parameters;
  const SeededDomain seeded(problem);
  CGAL::perturb_mesh_3(complex, seeded.domain, params::time_limit = 0, params::sliver_bound = kPerturbBound);
  CGAL::exude_mesh_3(complex, params::time_limit = 0, params::sliver_bound = 0.0);
}

TetMesh toTetMesh(const Complex& complex, const MeshingProblem& problem) {
  TetMesh mesh;
  // Nodes are numbered in the order the cells meet them, so the hash only has
  // to be consistent within the call.
  const auto hash = [](Triangulation::Vertex_handle v) { return std::hash<const void*>()(&*v); };
  std::unordered_map<Triangulation::Vertex_handle, int32_t, decltype(hash)> index(0, hash);
  const auto nodeOf = [&](Triangulation::Vertex_handle v) {
    const auto [it, inserted] = index.try_emplace(v, static_cast<int32_t>(mesh.nodes.size()));
    if (inserted) {
      const auto& p = v->point().point();
      mesh.nodes.push_back(Vec3(p.x(), p.y(), p.z()) + problem.offset);
    }
    return it->second;
  };
  mesh.tets.reserve(complex.number_of_cells_in_complex());
  for (auto cell = complex.cells_in_complex_begin(); cell != complex.cells_in_complex_end(); ++cell) {
    TetIndices tet;
    for (int i = 0; i < 4; ++i) tet[i] = nodeOf(cell->vertex(i));
    const auto& n = mesh.nodes;
    if (signedVolume(n[tet[0]], n[tet[1]], n[tet[2]], n[tet[3]]) < 0) std::swap(tet[2], tet[3]);
    mesh.tets.push_back(tet);
    mesh.labels.push_back(problem.labelled ? int32_t(complex.subdomain_index(cell)) : 1);
  }
  return mesh;
}

TetMesh meshToCount(const MeshingProblem& problem, int targetTets) {
  if (targetTets < kMinTargetTets || targetTets > kMaxTargetTets)
    throw std::invalid_argument("target tetrahedron count " + std::to_string(targetTets) +
                                " is outside [" + std::to_string(kMinTargetTets) + ", " +
                                std::to_string(kMaxTargetTets) + "]");
  // Exudation removes about 4% of the refined mesh's tets (slivers flipped
  // away), whatever the size: refinement aims at the count before it.
  const double refinedTarget = targetTets / kSliverRemovalRetention;
  // First guess of the cell size s (mm) from the solid's estimate of the
  // refined count, solved for s by fixed-point iteration.
  double size = std::cbrt(problem.volumeTerm / refinedTarget);
  for (int i = 0; i < 20; ++i)
    size = std::cbrt(problem.volumeTerm /
                     std::max(refinedTarget - problem.surfaceTerm / (size * size), 0.1 * refinedTarget));
  double exponent = -3.0;  // d log(count) / d log(size), refined from the runs
  Complex best;
  double bestError = std::numeric_limits<double>::infinity(), lastSize = 0.0, lastCount = 0.0;
  for (int run = 0; run < kMaxRuns && bestError > kAim; ++run) {
    Complex complex = refine(problem, size);
    const double count = static_cast<double>(complex.number_of_cells_in_complex());
    const double error = std::abs(count / refinedTarget - 1.0);
    if (error < bestError) {
      bestError = error;
      best.swap(complex);
    }
    if (lastCount > 0 && std::abs(std::log(size / lastSize)) > 1e-3) {
      const double slope = std::log(count / lastCount) / std::log(size / lastSize);
      if (std::isfinite(slope)) exponent = std::clamp(slope, -4.0, -1.5);
    }
    lastSize = size;
    lastCount = count;
    size *= std::pow(refinedTarget / std::max(count, 1.0), 1.0 / exponent);
  }
  removeSlivers(problem, best);
  return toTetMesh(best, problem);
}

TetMesh meshAtSize(const MeshingProblem& problem, double size) {
  if (!(size > 0) || !std::isfinite(size)) throw std::invalid_argument("the cell size must be a positive number of mm");
  Complex complex = refine(problem, size);
  removeSlivers(problem, complex);
  return toTetMesh(complex, problem);
}

// The image in CGAL's form, padded with a voxel of label 0 on every side so
// that regions touching the image's border are closed, with the count model
// from the labelled volume and the area between labels.
MeshingProblem labelledProblem(const LabelledImage& image) {
  // Named copies, not a structured binding: the lambda below captures them.
  const int nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
  if (nx <= 0 || ny <= 0 || nz <= 0 || image.labels.size() != size_t(nx) * ny * nz)
    throw std::invalid_argument("the labelled image's size does not match its labels");
  if (!(image.spacing.minCoeff() > 0) || !image.spacing.allFinite() || !image.origin.allFinite())
    throw std::invalid_argument("the labelled image's spacing must be positive and its origin finite");
  const int px = nx + 2, py = ny + 2, pz = nz + 2;
  _image* raw = ::_createImage(px, py, pz, 1, image.spacing.x(), image.spacing.y(), image.spacing.z(), 4, WK_FIXED,
                               SGN_SIGNED);
  if (raw == nullptr) throw std::bad_alloc();
  CGAL::Image_3 cgalImage(raw);  // owns raw
  auto* padded = static_cast<int32_t*>(raw->data);
  std::memset(padded, 0, size_t(px) * py * pz * sizeof(int32_t));
  size_t labelled = 0, interfaces[3] = {0, 0, 0};
  auto at = [&](int i, int j, int k) { return image.labels[size_t(i) + size_t(nx) * (size_t(j) + size_t(ny) * k)]; };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int32_t label = at(i, j, k);
        if (label < 0) throw std::invalid_argument("label " + std::to_string(label) + " is negative (expected 0 outside, 1 and up inside)");
        padded[size_t(i + 1) + size_t(px) * (size_t(j + 1) + size_t(py) * (k + 1))] = label;
        labelled += label != 0;
        // Faces between different labels, the image border counting as 0.
        interfaces[0] += label != (i + 1 < nx ? at(i + 1, j, k) : 0);
        interfaces[1] += label != (j + 1 < ny ? at(i, j + 1, k) : 0);
        interfaces[2] += label != (k + 1 < nz ? at(i, j, k + 1) : 0);
        interfaces[0] += i == 0 && label != 0;
        interfaces[1] += j == 0 && label != 0;
        interfaces[2] += k == 0 && label != 0;
      }
  if (labelled == 0) throw std::invalid_argument("the labelled image has no voxel with a label other than 0");
  const Vec3& h = image.spacing;
  MeshingProblem problem;
  problem.makeDomain = [cgalImage](CGAL::Random& random) {
    return Domain::create_labeled_image_mesh_domain(cgalImage, CGAL::parameters::relative_error_bound = kRelativeErrorBound,
                                                    CGAL::parameters::value_outside = 0,
                                                    CGAL::parameters::p_rng = &random);
  };
  // As for a smooth solid (ImplicitSolid), with the staircase area counted
  // at two thirds (a voxelised smooth surface has 1.5 times its area).
  problem.volumeTerm = 4.2 * double(labelled) * h.prod();
  problem.surfaceTerm = 4.3 * (2.0 / 3.0) *
                        (double(interfaces[0]) * h.y() * h.z() + double(interfaces[1]) * h.x() * h.z() +
                         double(interfaces[2]) * h.x() * h.y());
  // Facets closer than a voxel to the staircase would follow its steps.
  problem.leastFacetDistance = h.maxCoeff();
  problem.initialize = [cgalImage](Complex& complex, const Domain& domain, const Criteria& criteria) {
    // It draws its ray directions from CGAL's default generator, seeded here
    // so that the mesh depends only on the image, and reports its progress on
    // standard output, which is silenced while it runs.
    CGAL::get_default_random() = CGAL::Random(kSeed);
    std::streambuf* const shown = std::cout.rdbuf(nullptr);
    try {
      initialize_triangulation_from_labeled_image(complex, domain, cgalImage, criteria, int32_t(0));
    } catch (...) {
      std::cout.rdbuf(shown);
      throw;
    }
    std::cout.rdbuf(shown);
  };
  // CGAL's voxel (i, j, k) of the padded image is at (i, j, k) * spacing.
  problem.offset = image.origin - h;
  problem.labelled = true;
  return problem;
}

}  // namespace

class CgalTetMesher final : public TetMesher {
 public:
  TetMesh meshImplicitSolid(const ImplicitSolid& solid, int targetTets) const override {
    return meshToCount(implicitProblem(solid), targetTets);
  }
  TetMesh meshImplicitSolidAtSize(const ImplicitSolid& solid, double size) const override {
    return meshAtSize(implicitProblem(solid), size);
  }
  TetMesh meshLabelledImage(const LabelledImage& image, int targetTets) const override {
    return meshToCount(labelledProblem(image), targetTets);
  }
  TetMesh meshLabelledImageAtSize(const LabelledImage& image, double size) const override {
    return meshAtSize(labelledProblem(image), size);
  }
};

std::shared_ptr<TetMesher> makeCgalTetMesher() { return std::make_shared<CgalTetMesher>(); }

}  // namespace trephine::meshing
