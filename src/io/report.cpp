// The run report as JSON (nlohmann-json).
#include <nlohmann/json.hpp>

#include <cmath>

#include "froth/io.hpp"
#include "froth/partition.hpp"
#include "froth/quality.hpp"
#include "froth/weld.hpp"
#include "io/atomic_file.hpp"

namespace froth {

std::string report_json_text(const RunReport& run, const PartitionSummary* partition) {
  nlohmann::ordered_json j;
  j["froth_version"] = FROTH_VERSION;
  j["input"] = {{"domain", run.domain}, {"r", run.r}, {"random_seed", run.seed}, {"weld", run.weld},
                {"threads", run.threads}};
  const auto& f = run.features;
  j["features"] = {{"angle_degrees", f.angle_degrees}, {"flat_edges", f.flat_edges},
                     {"flat_reflex_edges", f.flat_reflex_edges},
                   {"convex_edges", f.convex_edges},   {"reflex_edges", f.reflex_edges},
                   {"curves", f.curves},               {"convex_curves", f.convex_curves},
                   {"reflex_curves", f.reflex_curves}, {"corners", f.corners}};
  j["input"]["grade"] = run.grade;
  if (run.grade) j["input"]["min_r"] = run.min_r, j["input"]["max_grading"] = run.grading;
  if (run.cells_requested > 0) j["input"]["cells_requested"] = run.cells_requested;
  j["input"]["convex"] = run.input.convex;
  j["input"]["triangles"] = run.input.triangles;
  j["input"]["shells"] = run.input.shells;
  j["input"]["cavities"] = run.input.cavities;
  j["input"]["reoriented_triangles"] = run.input.reoriented_triangles;
  const auto& s = run.sampling;
  j["sampling"] = {{"seeds", s.seeds},
                   {"edge_seeds", s.edge_seeds},
                   {"vertex_seeds", s.vertex_seeds},
                   {"darts", s.darts},
                   {"refinement_levels", s.levels},
                   {"uncovered_cubes", s.uncovered_cubes},
                   {"maximal", s.uncovered_cubes == 0},
                   {"protection_radius_reduced", s.protection_radius_reduced},
                   {"smallest_protection_radius_over_h", s.smallest_protection_radius},
                   {"base_cube_side", s.base_cube_side},
                   {"grid", s.grid}};
  for (const auto& l : s.per_level)
    j["sampling"]["per_level"].push_back({{"active_cubes", l.active_cubes}, {"darts", l.darts}, {"accepted", l.accepted}});
  j["mesh"] = {{"cells", run.cells},
               {"interior_cells", run.interior_cells},
               {"fringe_cells", run.fringe_cells},
               {"edge_cells", run.edge_cells},
               {"vertex_cells", run.vertex_cells},
               {"interface_cells", run.interface_cells},
               {"faces", run.faces},
               {"seeds_split_in_pieces", run.split_seeds},
               {"cells_added_by_pieces", run.extra_pieces},
               {"cells_cut_by_seeds_beyond_2r", run.recut_cells},
               {"points", run.points}};
  for (const RunReport::Region& r : run.regions)
    j["regions"].push_back({{"name", r.name}, {"cells", r.cells}, {"volume", r.volume}, {"enclosed_volume", r.enclosed}});
  for (const RunReport::Interface& i : run.interfaces)
    j["interfaces"].push_back({{"regions", {run.regions[size_t(i.a)].name, run.regions[size_t(i.b)].name}},
                               {"area", i.area},
                               {"area_from_first", i.from_a},
                               {"area_from_second", i.from_b}});
  for (const RunReport::Crack& c : run.cracks)
    j["cracks"].push_back({{"name", c.name},
                           {"input_area", c.input_area},
                           {"area", c.area},
                           {"clipped", c.clipped},
                           {"front_length", c.front_length},
                           {"area_from_a", c.from_a},
                           {"area_from_b", c.from_b},
                           {"faces_a", c.faces_a},
                           {"faces_b", c.faces_b},
                           {"faces_on_front", c.faces_on_front}});
  if (!run.cracks.empty())
    j["sampling"].update({{"crack_curve_seeds", s.crack_edge_seeds}, {"crack_sheet_seeds", s.crack_face_seeds}});
  if (!run.regions.empty())
    j["sampling"].update({{"interface_edge_seeds", s.interface_edge_seeds},
                          {"interface_face_seeds", s.interface_face_seeds},
                          {"interface_uncovered_subtriangles", s.interface_uncovered},
                          {"interface_curve_disk_over_h", s.interface_curve_factor},
                          {"interface_facet_disk_over_h", s.interface_facet_factor}});
  if (run.convex_split.requested) {
    const RunReport::ConvexSplit& cs = run.convex_split;
    j["convex"] = {{"cells_split", cs.cells_split},
                   {"pieces", cs.pieces},
                   {"most_pieces_of_a_cell", cs.max_pieces},
                   {"cells_left_nonconvex", cs.left_nonconvex},
                   {"left_vertex_beyond_face_plane_over_r", cs.left_violation},
                   {"smallest_piece_volume_over_r3", cs.smallest_piece_volume},
                   {"piece_aspect_mean", cs.piece_aspect_mean},
                   {"piece_aspect_max", cs.piece_aspect_max},
                   {"piece_min_dihedral", cs.piece_min_dihedral},
                   {"pieces_without_inscribed_ball", cs.pieces_without_ball}};
  }
  j["volume"] = {{"domain", run.domain_volume},
                 {"cells_sum", run.volume_sum},
                 {"relative_error", run.volume_relative_error()}};
  j["border_area"] = {{"surface", run.surface_area}, {"border_faces", run.border_area}};
  if (run.feature_size.measured) {
    // Values not below the cap are null (JSON has no infinity).
    auto number = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
    auto measure = [&](const FeatureSizeReport::Measure& m) {
      nlohmann::ordered_json out = {{"min", number(m.min)}, {"area_fraction_below_cap", m.area_below_cap},
                                    {"quantile_1", number(m.quantile_1)}, {"quantile_10", number(m.quantile_10)},
                                    {"quantile_50", number(m.quantile_50)}};
      if (std::isfinite(m.min)) out["where"] = {m.where.x, m.where.y, m.where.z};
      return out;
    };
    j["feature_size"] = {{"cap", run.feature_size.cap},
                         {"thickness", measure(run.feature_size.thickness)},
                         {"gap", measure(run.feature_size.gap)}};
  }
  if (run.sizing.graded || run.sizing.floor_raised)
    j["sizing"] = {{"graded", run.sizing.graded},
                   {"min_r", run.sizing.min_r},
                   {"grading", run.sizing.grading},
                   {"lipschitz_bound", run.sizing.lipschitz},
                   {"smallest_h", run.sizing.smallest},
                   {"floor_raised", run.sizing.floor_raised},
                   {"volume_fraction_graded", run.sizing.graded_fraction},
                   {"estimated_cell_ratio", run.sizing.cell_ratio}};
  j["star_shaped"] = {{"cells_not_star_shaped", run.not_star_shaped}, {"worst_face_plane_beyond_seed_over_r", run.star_violation},
                        {"cells_without_kernel", run.without_kernel}, {"cells_without_center", run.without_center}};
  nlohmann::ordered_json stages = nlohmann::ordered_json::object();
  nlohmann::ordered_json peaks = nlohmann::ordered_json::object();
  for (const auto& st : run.stages) stages[st.stage] = st.seconds, peaks[st.stage] = st.peak_rss_bytes;
  if (run.welding) {
    const WeldStats& w = *run.welding;
    j["welding"] = {{"tolerance", w.tolerance},
                    {"edges_collapsed", w.edges_collapsed},
                    {"faces_removed", w.faces_removed},
                    {"clusters_refused", w.clusters_refused},
                    {"shortest_edge_before", w.shortest_edge_before},
                    {"shortest_edge_after", w.shortest_edge_after},
                    {"max_vertex_displacement", w.max_displacement},
                    {"max_face_nonplanarity_over_r", w.max_nonplanarity},
                    {"volume_change_bound", w.volume_change_bound()},
                    {"volume_change", run.volume_sum - run.domain_volume}};
  }
  if (run.quality) j["quality"] = nlohmann::ordered_json::parse(quality_json_text(*run.quality));
  if (run.bounds_before_weld) {
    j["quality_before_welding"] = {
        {"bounds", nlohmann::ordered_json::parse(quality_json_text(*run.bounds_before_weld))["bounds"]}};
    j["welding_shift"] = {{"max_aspect_change", run.weld_aspect_shift},
                          {"max_dihedral_change_degrees", run.weld_dihedral_shift}};
  }
  j["seconds"] = stages;
  j["peak_memory_bytes_after_stage"] = peaks;
  j["seconds_total"] = run.total_seconds;
  j["peak_memory_bytes"] = run.peak_rss_bytes;
  if (partition) {
    size_t owned = 0, ghosts = 0;
    nlohmann::ordered_json ranks = nlohmann::ordered_json::array();
    for (size_t k = 0; k < partition->ranks.size(); ++k) {
      const PartitionReport& p = partition->ranks[k];
      owned += p.owned_seeds, ghosts += p.ghost_seeds;
      ranks.push_back({{"rank", p.rank},
                       {"layers", {p.slab.owned_begin, p.slab.owned_end}},
                       {"first_seed", p.first_seed},
                       {"seeds", p.owned_seeds},
                       {"ghost_seeds", p.ghost_seeds},
                       {"ghost_cells", p.ghost_cells},
                       {"faces_shared_with_other_ranks", p.partition_faces},
                       {"sampling_exchanges", p.exchanges},
                       {"seconds", partition->rank_seconds[k]},
                       {"peak_memory_bytes", partition->rank_peak_rss[k]}});
    }
    j["partition"] = {{"ranks", partition->ranks.size()},
                      {"axis", "z"},
                      {"sampling_halo_layers", kSamplingHaloLayers},
                      {"cell_halo_layers", kCellHaloLayers},
                      {"ghost_cell_layers", kGhostCellLayers},
                      {"ghost_over_owned_seeds", owned ? double(ghosts) / double(owned) : 0.0},
                      {"per_rank", ranks}};
  }
  return j.dump(2) + "\n";
}

void write_quality_json(const QualityReport& q, const std::string& mesh, const std::filesystem::path& path) {
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(quality_json_text(q));
  nlohmann::ordered_json out;
  out["froth_version"] = FROTH_VERSION;
  out["mesh"] = mesh;
  for (auto& [k, v] : j.items()) out[k] = v;
  const std::string text = out.dump(2) + "\n";
  write_atomically(path, [&](std::ostream& o) { o << text; });
}

void write_report_json(const RunReport& run, const std::filesystem::path& path, const PartitionSummary* partition) {
  std::string text = report_json_text(run, partition);
  write_atomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace froth
