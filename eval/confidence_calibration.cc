#include "eval/confidence_calibration.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>

#include "absl/strings/str_cat.h"
#include "eval/fixed_format.h"
#include "eval/svg_chart.h"

namespace mocap::eval {

void AddConfidenceSamples(const ReconstructedFrame& frame, float scale,
                          const std::array<Eigen::Vector3f, kNumBodyLandmarks>& output,
                          const std::array<Eigen::Vector3f, kNumBodyLandmarks>& truth,
                          std::vector<ConfidenceSample>* samples) {
  for (int k = 0; k < kNumBodyLandmarks; ++k) {
    samples->push_back({.predicted = scale * frame.landmark_error[k],
                        .actual = (output[k] - truth[k]).norm(),
                        .landmark = static_cast<std::uint8_t>(k),
                        .cues = ConfidenceCuesOf(frame.diagnostics),
                        .segment = frame.segment,
                        .frame_in_segment = frame.frame_in_segment});
  }
}

namespace {

// Ranks 1..n, ties sharing their mean rank.
std::vector<double> Ranks(const std::vector<float>& values) {
  std::vector<int> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return values[a] < values[b]; });
  std::vector<double> ranks(values.size());
  for (size_t i = 0; i < order.size();) {
    size_t j = i;
    while (j + 1 < order.size() && values[order[j + 1]] == values[order[i]]) ++j;
    const double rank = 0.5 * static_cast<double>(i + j) + 1.0;
    for (size_t k = i; k <= j; ++k) ranks[order[k]] = rank;
    i = j + 1;
  }
  return ranks;
}

double Pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  if (n < 2) return 0;
  const double ma = std::accumulate(a.begin(), a.end(), 0.0) / n, mb = std::accumulate(b.begin(), b.end(), 0.0) / n;
  double ab = 0, aa = 0, bb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ab += (a[i] - ma) * (b[i] - mb);
    aa += (a[i] - ma) * (a[i] - ma);
    bb += (b[i] - mb) * (b[i] - mb);
  }
  return aa > 0 && bb > 0 ? ab / std::sqrt(aa * bb) : 0.0;
}

double Spearman(const std::vector<float>& predicted, const std::vector<float>& actual) {
  return Pearson(Ranks(predicted), Ranks(actual));
}

}  // namespace

ConfidenceSummary SummariseConfidence(const std::vector<ConfidenceSample>& samples, int bins) {
  ConfidenceSummary summary;
  summary.samples = static_cast<long>(samples.size());
  if (samples.empty()) return summary;
  std::vector<float> predicted, actual;
  predicted.reserve(samples.size());
  actual.reserve(samples.size());
  for (const ConfidenceSample& s : samples) {
    predicted.push_back(s.predicted);
    actual.push_back(s.actual);
  }
  summary.spearman = Spearman(predicted, actual);
  int landmarks = 0;
  for (int k = 0; k < kNumBodyLandmarks; ++k) {
    std::vector<float> p, a;
    for (const ConfidenceSample& s : samples) {
      if (s.landmark != k) continue;
      p.push_back(s.predicted);
      a.push_back(s.actual);
    }
    if (p.size() < 2) continue;
    summary.spearman_by_landmark[k] = Spearman(p, a);
    summary.spearman_within_landmarks += summary.spearman_by_landmark[k];
    ++landmarks;
  }
  if (landmarks > 0) summary.spearman_within_landmarks /= landmarks;

  std::vector<int> order(samples.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return predicted[a] < predicted[b]; });
  const int count = std::max(1, std::min(bins, static_cast<int>(samples.size())));
  for (int b = 0; b < count; ++b) {
    const size_t from = order.size() * b / count, to = order.size() * (b + 1) / count;
    ReliabilityBin bin;
    for (size_t i = from; i < to; ++i) {
      bin.predicted += predicted[order[i]];
      bin.actual += actual[order[i]];
    }
    bin.count = static_cast<long>(to - from);
    if (bin.count == 0) continue;
    bin.predicted /= static_cast<double>(bin.count);
    bin.actual /= static_cast<double>(bin.count);
    if (bin.predicted > 0 && bin.actual > 0) {
      summary.worst_bin_ratio =
          std::max(summary.worst_bin_ratio, std::max(bin.actual / bin.predicted, bin.predicted / bin.actual));
    }
    summary.bins.push_back(bin);
  }
  return summary;
}

std::filesystem::path ConfidenceSamplesFile(const std::filesystem::path& file, const std::string& run) {
  if (run == "full") return file;
  std::filesystem::path named = file;
  named.replace_filename(absl::StrCat(file.stem().string(), ".", run, file.extension().string()));
  return named;
}

absl::Status WriteConfidenceSamples(const std::vector<ConfidenceSample>& samples, const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) return absl::UnavailableError(absl::StrCat("cannot write ", file.string()));
  out << "clip,segment,frame_in_segment,landmark,predicted_m,actual_m,distance,wrist_fit_m,solver_cost,"
         "session_log_cost,untracked_s,fading_guess_weight\n";
  for (const ConfidenceSample& s : samples) {
    const ConfidenceCues& c = s.cues;
    out << s.clip << ',' << s.segment << ',' << s.frame_in_segment << ',' << kBodyLandmarkNames[s.landmark] << ','
        << s.predicted << ',' << s.actual << ',' << c.distance << ',' << c.wrist_fit << ',' << c.solver_cost << ','
        << c.session_log_cost << ',' << UntrackedSecondsFor(c, s.landmark) << ','
        << FadingGuessFor(c, s.landmark).weight << '\n';
  }
  out.close();
  if (!out) return absl::DataLossError(absl::StrCat("writing ", file.string(), " failed"));
  return absl::OkStatus();
}

nlohmann::json ConfidenceJson(const ConfidenceSummary& summary) {
  nlohmann::json json = {{"pairs", summary.samples},
                         {"spearman", summary.spearman},
                         {"spearman_within_landmarks", summary.spearman_within_landmarks},
                         {"worst_bin_actual_over_predicted", summary.worst_bin_ratio}};
  for (int k = 0; k < kNumBodyLandmarks; ++k)
    json["spearman_by_landmark"][kBodyLandmarkNames[k]] = summary.spearman_by_landmark[k];
  for (const ReliabilityBin& bin : summary.bins) {
    json["reliability"].push_back(
        {{"predicted_cm", 100 * bin.predicted}, {"actual_cm", 100 * bin.actual}, {"pairs", bin.count}});
  }
  return json;
}

std::string ConfidenceMarkdown(const std::vector<std::pair<std::string, const ConfidenceSummary*>>& rows) {
  std::string md =
      "| | (frame, landmark) pairs | Spearman | within landmarks | worst bin (factor) | actual / predicted per bin, "
      "least predicted first |\n|---|---|---|---|---|---|\n";
  for (const auto& [name, summary] : rows) {
    std::string bins;
    for (const ReliabilityBin& bin : summary->bins)
      absl::StrAppend(&bins, bins.empty() ? "" : " ", Fixed(bin.predicted > 0 ? bin.actual / bin.predicted : 0.0));
    absl::StrAppend(&md, "| ", name, " | ", summary->samples, " | ", Fixed(summary->spearman), " | ",
                    Fixed(summary->spearman_within_landmarks), " | ", Fixed(summary->worst_bin_ratio), " | ", bins,
                    " |\n");
  }
  return md;
}

std::string ReliabilitySvg(const std::string& title, const ConfidenceSummary& summary) {
  std::vector<double> x;
  Series actual{"actual", {}}, ideal{"predicted", {}}, high{"predicted × 1.5", {}}, low{"predicted ÷ 1.5", {}};
  for (const ReliabilityBin& bin : summary.bins) {
    x.push_back(100 * bin.predicted);
    actual.values.push_back(100 * bin.actual);
    ideal.values.push_back(100 * bin.predicted);
    high.values.push_back(150 * bin.predicted);
    low.values.push_back(100 * bin.predicted / 1.5);
  }
  return LineChartSvg(title, "predicted error, bin mean (cm)", "actual error, bin mean (cm)", x,
                      {actual, ideal, high, low});
}

}  // namespace mocap::eval
