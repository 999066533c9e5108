#include "summary.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace froth_cli {
namespace {

std::string line(const char* label, const std::string& text) { return fmt::format("  {:<10}{}\n", label, text); }

std::string join(const std::vector<std::string>& parts) {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : ", ") + p;
  return out;
}

// What a user should know about this mesh: the chosen r, repairs, thin features, cells that are
// not star-shaped from their seed. Printed unless --quiet.
std::vector<std::string> notes(const froth::RunReport& run) {
  std::vector<std::string> out;
  if (run.cells_requested > 0)
    out.push_back(fmt::format("r = {} was chosen for about {:.6g} cells; -r {} repeats this mesh", run.r,
                              run.cells_requested, run.r));
  if (run.welding && run.welding->clusters_refused > 0)
    out.push_back(fmt::format(
        "welding refused {} clusters of vertices closer than w = {:.3g} = {:.3g} r (merging one would pinch a face, "
        "move a vertex off the surface or flatten a cell), and collapsed {} edges. A cluster is every vertex joined "
        "to it by edges shorter than w and is refused whole, so a larger w, whose clusters join, can collapse fewer "
        "edges: keep w well below r (the default is 1e-4 r)",
        run.welding->clusters_refused, run.welding->tolerance, run.welding->tolerance / run.r,
        run.welding->edges_collapsed));
  for (const froth::RunReport::Crack& c : run.cracks)
    if (c.faces_on_front > 0)
      out.push_back(fmt::format("crack {}: {} of its {} faces on side a have every point on the front (the sheet is "
                                "narrower than the cells there): their twins on side b have the same points, so a "
                                "reader that pairs faces by their points takes each pair for one shared face; a "
                                "smaller r avoids them",
                                c.name, c.faces_on_front, c.faces_a));
  if (run.input.reoriented_triangles)
    out.push_back(fmt::format("--repair reoriented {} triangles", run.input.reoriented_triangles));
  for (const auto& [what, m] : {std::pair{"walls", run.feature_size.thickness}, std::pair{"gaps", run.feature_size.gap}})
    if (std::isfinite(m.min))
      out.push_back(fmt::format("{} narrower than {}r on {:.3g}% of the surface (narrowest {:.3g} = {:.3g} r, at "
                                "({:.4g}, {:.4g}, {:.4g})): a smaller r or --grade resolves them",
                                what, run.feature_size.cap > run.r ? "2" : "", 100 * m.area_below_cap, m.min,
                                m.min / run.r, m.where.x, m.where.y, m.where.z));
  if (run.sizing.graded)
    out.push_back(fmt::format("sizing graded to the walls and gaps: h from {:.3g} (= {:.3g} r, floor --min-r {:.3g}{}) "
                              "to r, slope at most {:.2g}; h < r on {:.3g}% of the volume, about {:.3g} times a "
                              "uniform mesh's cells",
                              run.sizing.smallest, run.sizing.smallest / run.r, run.sizing.min_r,
                              run.sizing.floor_raised ? ", raised from r/4 to keep the cells within budget" : "",
                              run.sizing.lipschitz, 100 * run.sizing.graded_fraction, run.sizing.cell_ratio));
  else if (run.sizing.floor_raised)
    out.push_back("sizing not graded: resolving the walls and gaps would cost more than the default budget of cells; "
                  "give --min-r to grade anyway");
  if (run.split_seeds > 0)
    out.push_back(fmt::format("{} seeds saw the domain in several pieces ({}): their pieces became {} more cells (cell "
                              "data piece > 0)",
                              run.split_seeds,
                              run.cracks.empty() ? "a wall or gap thinner than r" : "a crack, or a wall or gap thinner than r",
                              run.extra_pieces));
  if (run.convex_split.requested) {
    const froth::RunReport::ConvexSplit& cs = run.convex_split;
    out.push_back(cs.cells_split == 0
                      ? std::string("--convex: every cell was convex already")
                      : fmt::format("--convex split {} non-convex cells into {} convex pieces (up to {} from one cell; "
                                    "cell data parent); the smallest piece {:.3g} r^3{}{}",
                                    cs.cells_split, cs.pieces, cs.max_pieces, cs.smallest_piece_volume,
                                    cs.piece_aspect_max > 0
                                        ? fmt::format(", pieces' aspect ratio mean {:.3g}, largest {:.3g}{}", cs.piece_aspect_mean,
                                                      cs.piece_aspect_max,
                                                      cs.pieces_without_ball
                                                          ? fmt::format(" ({} without an inscribed ball found)", cs.pieces_without_ball)
                                                          : "")
                                        : "",
                                    cs.left_nonconvex ? fmt::format("; {} cells left non-convex by up to {:.2g} r (no face "
                                                                    "plane cuts them cleanly)",
                                                                    cs.left_nonconvex, cs.left_violation)
                                                      : ""));
  }
  if (run.not_star_shaped > 0)
    out.push_back(fmt::format("{} cells are not star-shaped from their seed (a face plane up to {:.3g} r beyond it): "
                              "they lie along concave curved surfaces, whose flat reflex edges are not protected, or "
                              "where features are closer than r; cell data center is a point they are star-shaped from",
                              run.not_star_shaped, run.star_violation));
  if (run.without_kernel > 0)
    out.push_back(fmt::format("{} of them are star-shaped from no point (empty kernel): they wrap around a feature "
                              "thinner than r; a smaller r avoids them",
                              run.without_kernel));
  if (run.sampling.protection_radius_reduced > 0)
    out.push_back(fmt::format("{} protection seeds lie closer to another than their spacing allows (reflex corners or "
                              "short reflex curves closer than r/sqrt(2)): their cell data radius is what holds, down "
                              "to {:.3g} of h",
                              run.sampling.protection_radius_reduced, run.sampling.smallest_protection_radius));
  if (run.without_center > 0)
    out.push_back(fmt::format("{} cells have no point to fan them from: cell data kernel is 0 and center NaN there",
                              run.without_center));
  return out;
}

std::string quality_text(const froth::RunReport& run) {
  const froth::QualityReport& q = *run.quality;
  const froth::QualityReport& b = run.bounds_before_weld ? *run.bounds_before_weld : q;  // the bounds hold before welding
  std::string text = interior_aspect_text(q);
  if (q.cells[0] > 0)
    text += fmt::format(", interior dihedrals {:.1f} to {:.1f} degrees", q.dihedral[0].min, q.dihedral[0].max);
  return text + fmt::format("; cells beyond the paper's bounds{}: {} (Theorem 1), {} and {} (Lemma 6)",
                            run.bounds_before_weld ? " before welding" : "", b.theorem1_violations,
                            b.lemma6_interior_violations, b.lemma6_border_violations);
}

std::string time_text(const froth::RunReport& run) {
  std::vector<froth::StageTiming> stages = run.stages;
  std::sort(stages.begin(), stages.end(), [](const auto& a, const auto& b) { return a.seconds > b.seconds; });
  std::vector<std::string> largest;
  for (size_t k = 0; k < std::min<size_t>(3, stages.size()); ++k)
    largest.push_back(fmt::format("{} {:.3f} s", stages[k].stage, stages[k].seconds));
  return fmt::format("{:.3f} s on {} thread{}, peak memory {:.1f} MiB ({})", run.total_seconds, run.threads,
                     run.threads == 1 ? "" : "s", run.peak_rss_bytes / 1048576.0, join(largest));
}

std::string details(const froth::RunReport& run) {
  const froth::FeatureSummary& f = run.features;
  const auto& in = run.input;
  std::string out = line("input", fmt::format("{} triangles, {} shell{} ({} cavit{}), {}", in.triangles, in.shells,
                                              in.shells == 1 ? "" : "s", in.cavities, in.cavities == 1 ? "y" : "ies",
                                              in.convex ? "convex" : "non-convex: cells clipped to the surface"));
  out += line("features", fmt::format("over {} degrees: {} convex and {} reflex edges in {} curves, {} corners; {} "
                                      "flat edges ({} of them concave)",
                                      f.angle_degrees, f.convex_edges, f.reflex_edges, f.curves, f.corners,
                                      f.flat_edges, f.flat_reflex_edges));
  out += line("sampling", fmt::format("{} seeds from {} darts, {} refinement levels, maximal; protection: {} vertex and "
                                      "{} edge seeds on the reflex edges",
                                      run.sampling.seeds, run.sampling.darts, run.sampling.levels,
                                      run.sampling.vertex_seeds, run.sampling.edge_seeds));
  if (run.welding) {
    const froth::WeldStats& w = *run.welding;
    out += line("welding", fmt::format("w = {:.3g}: {} edges collapsed, {} faces removed, {} clusters refused, shortest "
                                       "edge {:.3g} -> {:.3g}, vertices moved at most {:.3g}, faces non-planar by at "
                                       "most {:.2g} r",
                                       w.tolerance, w.edges_collapsed, w.faces_removed, w.clusters_refused,
                                       w.shortest_edge_before,
                                       w.shortest_edge_after, w.max_displacement, w.max_nonplanarity));
  }
  if (run.quality) {
    const froth::QualityReport& b = run.bounds_before_weld ? *run.bounds_before_weld : *run.quality;
    std::string text = fmt::format("shortest edge {:.3g}", run.quality->shortest_edge);
    if (b.graded_cells > 0)
      text += fmt::format("; the bounds are judged where h = r, the {} cells with h < r at them or a neighbour are "
                          "counted apart: {}, {} and {} beyond them",
                          b.graded_cells, b.graded_outside.theorem1, b.graded_outside.lemma6_interior,
                          b.graded_outside.lemma6_border);
    if (run.bounds_before_weld)
      text += fmt::format("; welding moved aspect ratios by at most {:.2g} and dihedrals by at most {:.2g} degrees",
                          run.weld_aspect_shift, run.weld_dihedral_shift);
    out += line("measures", text);
  }
  std::vector<std::string> stages;
  for (const auto& st : run.stages) stages.push_back(fmt::format("{} {:.3f} s", st.stage, st.seconds));
  return out + line("stages", join(stages));
}

}  // namespace

std::string interior_aspect_text(const froth::QualityReport& q) {
  const auto& in = q.aspect[0];
  if (q.cells[0] == 0) return "no interior cells";
  return fmt::format("interior aspect ratio {:.3f} to {:.3f} (mean {:.3f})", in.min, in.max, in.mean());
}

std::string mesh_summary(const froth::RunReport& run, const std::vector<std::string>& written, Verbosity v) {
  if (v == Verbosity::Quiet) return "";
  std::string out = fmt::format("froth: meshed {} with r = {} and seed {}\n", run.domain, run.r, run.seed);
  const std::string interface_cells = run.regions.empty() ? "" : fmt::format(", {} interface", run.interface_cells);
  out += line("cells", fmt::format("{} ({} interior, {} fringe, {} edge, {} vertex{}), {} faces, {} points; every cell "
                                   "closed, every interior face matched",
                                   run.cells, run.interior_cells, run.fringe_cells, run.edge_cells, run.vertex_cells,
                                   interface_cells, run.faces, run.points));
  out += line("volume", fmt::format("cells sum {:.12g}, domain {:.12g} (relative error {:.2e})", run.volume_sum,
                                    run.domain_volume, run.volume_relative_error()));
  if (!run.regions.empty()) {
    std::vector<std::string> parts;
    for (const froth::RunReport::Region& r : run.regions) parts.push_back(fmt::format("{} {} cells", r.name, r.cells));
    out += line("regions", fmt::format("{}; {} interface cells on {} interfaces", join(parts), run.interface_cells,
                                       run.interfaces.size()));
  }
  for (const froth::RunReport::Crack& c : run.cracks)
    out += line("crack", fmt::format("{}: faces {:.6g} on side a, {:.6g} on side b, sheet {:.6g} inside the solid{}{}",
                                     c.name, c.from_a, c.from_b, c.area,
                                     c.clipped ? fmt::format(" (clipped from {:.6g})", c.input_area) : "",
                                     c.front_length > 0 ? fmt::format(", front {:.6g} long", c.front_length) : ""));
  if (run.quality) out += line("quality", quality_text(run));
  out += line("time", time_text(run));
  if (v == Verbosity::Verbose) out += details(run);
  out += line("wrote", join(written));
  for (const std::string& n : notes(run)) out += line("note", n);
  return out;
}

std::string quality_summary(const std::string& mesh, const froth::MeshCheck& check, const froth::QualityReport& q,
                            const std::vector<std::string>& written) {
  size_t cells = 0;
  for (auto n : q.cells) cells += n;
  std::string out = fmt::format("froth: {}\n", mesh);
  const uint64_t interface_cells = q.cells[size_t(froth::CellKind::InterfaceFace)] + q.cells[size_t(froth::CellKind::InterfaceEdge)];
  out += line("cells", fmt::format("{} polyhedral cells ({} interior, {} fringe, {} edge, {} vertex{}); {}", cells,
                                   q.cells[0], q.cells[1], q.cells[2], q.cells[3],
                                   interface_cells ? fmt::format(", {} interface", interface_cells) : std::string(),
                                   check.ok() ? "every cell closed, every shared face matched"
                                              : fmt::format("NOT VALID: {} open cells, {} unmatched faces, {} cells "
                                                            "of non-positive volume (first: {})",
                                                            check.open_cells, check.unmatched_faces,
                                                            check.nonpositive_cells, check.first_problem)));
  std::string text = interior_aspect_text(q);
  if (q.cells[0] > 0)
    text += fmt::format(", interior dihedrals {:.1f} to {:.1f} degrees", q.dihedral[0].min, q.dihedral[0].max);
  out += line("quality", text + fmt::format(", shortest edge {:.3g}; interior cells beyond Theorem 1: {}, beyond "
                                            "Lemma 6: {} interior, {} border-interior",
                                            q.shortest_edge, q.theorem1_violations, q.lemma6_interior_violations,
                                            q.lemma6_border_violations));
  if (!written.empty()) out += line("wrote", join(written));
  return out;
}

}  // namespace froth_cli
