// rayunits pareto (`rayunits pareto`, docs/PARETO.md): the non-dominated points of
// measured result rows on two or three axes (error, area, clock or throughput), per group (unit),
// and the cheapest point that meets a target, with its margin.
//
// Rows come from what the project writes: a sweep directory (its results.jsonl: each ok job's
// parameters merged with every row of its typed result), JSON Lines files (`synth --json` rows,
// synth/results/cell/*.jsonl), a JSON array, or a CSV table with a header (docs/trax/*.csv). A
// row is flattened to scalar fields, nested objects as "a.b" (a sweep row's parameters by their
// own names; the result's fields win where both have one).
//
// An axis names a field and a direction: "area_um2" (minimized: the direction is guessed from
// the name, see axis_direction), "psnr_db:max", "fmax_mhz:max". Three names are aliases that
// resolve, per group, to the first field every row of the group has:
//   area  -> area_um2, area_mm2, area_nand2                  (min)
//   fmax  -> fmax_mhz, rays_per_s, clock_mhz, fmax_est_mhz   (max)
//   error -> error_pct, error_fraction, unit_roundoff         (min)
// `unit_roundoff` is derived for rows that name a format (fields exp_bits/frac_bits or format):
// 2^-(M+1) for round-to-nearest, 2^-M for the directed roundings — the relative error bound of
// one correctly rounded operation (a bound that follows from the format, which the scoreboard
// proves each FP unit meets against MPFR; not a measurement of an image).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ru::pareto {

// Bad input (unreadable file, unknown field, bad axis or target): one line; the CLI exits 2.
struct ParetoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

using Row = nlohmann::ordered_json;  // one flat object: field -> number | string | bool | null

// The inputs with wildcard patterns ('*', '?', '[') expanded by glob(3) in sorted order (so a
// quoted 'synth/results/cell/fp_*.curve.jsonl' keeps the recorded command short); a pattern
// that matches nothing is an error.
std::vector<std::string> expand_inputs(const std::vector<std::string>& inputs);
// Every row of one input (see above). `source` is set on each row as field "source".
std::vector<Row> load_rows(const std::string& path);
// Flattens one object (nested objects as "a.b"; arrays of scalars kept as a string "a;b").
Row flatten(const nlohmann::json& j);
// Adds the derived fields (unit_roundoff, exp_bits/frac_bits from format) where they follow.
void derive(Row& r);

struct Axis {
  std::string field;   // as given ("area" or a field name)
  bool minimize = true;
};
// "FIELD" or "FIELD:min" / "FIELD:max".
Axis parse_axis(const std::string& spec);
// The guessed direction of a field name: max for fmax, clock, rays_per_s, throughput, psnr,
// _per_ (a rate), speed; min otherwise (error, area, latency, cycles, period, delay, ...).
bool axis_direction_minimize(const std::string& field);

struct Options {
  std::vector<Axis> axes;               // 2 or 3
  std::vector<std::string> group_by;    // fields; default: {"unit"} when rows have it
  std::vector<std::pair<std::string, std::string>> where;  // field = value (string compare)
  std::vector<std::string> label;       // fields naming a point (default: format, stages, round, ...)
};

struct Point {
  std::size_t row = 0;                  // index into the rows given to compute()
  std::string group;                    // "fp_add" or "fp_add flow=osu018" ("all" without group_by)
  std::string label;                    // "e5m10 s2 9270ps"
  std::vector<double> v;                // axis values (as measured, not negated)
  bool dominated = false;
  std::size_t dominated_by = 0;         // index into the points of the result (when dominated)
};

struct Group {
  std::string name;
  std::vector<std::string> fields;      // the resolved field of each axis in this group
  std::size_t points = 0, front = 0, no_value = 0;  // no_value: rows without a number on some axis
};

struct Result {
  std::vector<Axis> axes;
  std::vector<Group> groups;
  std::vector<Point> points;            // grouped, each group in input order
  std::vector<std::string> skipped;     // groups left out: "group 'noise': no row has a number in field ..."
};

// The fronts. A group where no row has a number on some axis is left out (Result::skipped);
// ParetoError when that leaves no group.
Result compute(const std::vector<Row>& rows, const Options& opt);

// "FIELD>=V", "FIELD<=V", "FIELD>V", "FIELD<V".
struct Target {
  std::string field;
  std::string op;
  double value = 0;
  bool met(double x) const;
  double margin(double x) const;  // >= 0 when met: how far past the threshold, in the field's unit
};
Target parse_target(const std::string& spec);

struct Pick {
  std::string group;
  std::optional<std::size_t> point;  // index into Result::points; empty: nothing meets the target
  double value = 0, margin = 0;      // the target field's value and margin of the pick
  std::size_t candidates = 0;        // points of the group with a value of the target field
};
// Per group, the point with the smallest cost axis (axes[cost_axis], oriented) that meets every
// target (rows without a target field's value cannot meet it); ties: the better other axes.
std::vector<Pick> cheapest(const Result& res, const std::vector<Row>& rows, const std::vector<Target>& targets,
                           std::size_t cost_axis = 1);

// A scene profile (`rayunits profile --json`) joined with unit rows: for every fraction width M
// the profile measured at its exponent width E (recommended_exp_bits), the format e{E}m{M} and
// every format of the rows with M fraction bits and more exponent bits (the image error is the
// profile's measurement at e{E}m{M}; a wider exponent is assumed no worse — it only removes
// overflow and underflow — and the table says where it was measured); per format, the summed cost (one row per unit: the one
// with the smallest cost-axis value at that format that meets `unit_targets`), and whether the
// profile's measurement meets its image target (error fraction and PSNR).
struct ProfileChoice {
  std::string format;
  std::string measured_at;              // the profile's format of this fraction width (e{E}m{M})
  bool meets = false;                   // the profile's image target at this fraction width
  double error_fraction = 0, psnr = 0;  // measured by the profile
  double cost = 0;                      // sum over the units of the cost field
  std::vector<std::pair<std::string, std::size_t>> unit_rows;  // unit -> row index
  std::vector<std::string> missing;     // units with no row at this format
};
struct ProfilePlan {
  std::string scene, cost_field;
  std::vector<std::string> units;
  double max_error_fraction = 0, min_psnr = 0;
  std::vector<ProfileChoice> formats;   // by fraction width
  std::optional<std::size_t> pick;      // cheapest that meets the target and has every unit
};
ProfilePlan plan_from_profile(const nlohmann::json& profile, const std::vector<Row>& rows, const Axis& cost,
                              const std::vector<Target>& unit_targets);

// pareto.csv: group, label, the axis fields, dominated, dominated_by, then every field of the row.
std::string points_csv(const Result& res, const std::vector<Row>& rows);
// Text for the terminal / Markdown: per group the front (and with `all` every point).
std::string front_markdown(const Result& res, const std::vector<Row>& rows, bool all);
std::string picks_markdown(const Result& res, const std::vector<Row>& rows, const std::vector<Target>& t,
                           const std::vector<Pick>& picks);
std::string plan_markdown(const ProfilePlan& p, const std::vector<Row>& rows);

}  // namespace ru::pareto
