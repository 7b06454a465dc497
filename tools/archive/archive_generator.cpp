#include "tools/archive/archive_generator.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/random.h"
#include "tools/archive/joint_markers.h"
#include "stages/ingest/ingest.h"
#include "stages/ingest/text_fields.h"

namespace syn {
namespace {

constexpr int kMarkers = 22;

// One source trial's joint centres: [frames][22] positions in metres, Z up.
struct SourceJoints {
  const SourceTrial* trial = nullptr;
  double rate = 120.0;
  std::vector<std::array<double, kMarkers * 3>> frames;
  double duration() const { return static_cast<double>(frames.size() - 1) / rate; }
};

bool LoadSource(const SourceTrial& trial, SourceJoints& joints) {
  const MarkerData capture = IngestCapture(trial.path, {}, nullptr);
  const BvhConvention convention = DetectBvhConvention(capture.bodies);
  if (convention == BvhConvention::kNone) return false;
  const int column = static_cast<int>(convention);
  std::array<int64_t, kMarkers> body{};
  for (int m = 0; m < kMarkers; ++m) {
    const std::string name = SmplJointMarkers()[static_cast<size_t>(m)].bvh[column];
    const auto found = std::find(capture.bodies.begin(), capture.bodies.end(), name);
    if (found == capture.bodies.end()) return false;
    body[static_cast<size_t>(m)] = found - capture.bodies.begin();
  }
  joints.trial = &trial;
  joints.rate = capture.rate_hz;
  const int64_t bodies = static_cast<int64_t>(capture.bodies.size());
  // The MotionBuilder- and Daz-friendly conversions start with a T-pose or reference frame (SOURCES.md).
  const int64_t first = convention == BvhConvention::kMax ? 0 : 1;
  for (int64_t t = first; t < capture.frame_count(); ++t) {
    std::array<double, kMarkers * 3> frame{};
    for (int m = 0; m < kMarkers; ++m) {
      const double* pose = &capture.body_pose[static_cast<size_t>((t * bodies + body[static_cast<size_t>(m)]) * 7)];
      for (int axis = 0; axis < 3; ++axis) frame[static_cast<size_t>(m * 3 + axis)] = pose[axis];
    }
    joints.frames.push_back(frame);
  }
  return joints.frames.size() >= 2;
}

int MirrorIndex(int marker) {
  const std::string mirror = SmplJointMarkers()[static_cast<size_t>(marker)].mirror;
  for (int m = 0; m < kMarkers; ++m) {
    if (mirror == SmplJointMarkers()[static_cast<size_t>(m)].smpl) return m;
  }
  return marker;
}

std::string TrcText(const std::string& file, double rate, const std::vector<std::array<double, kMarkers * 3>>& frames,
                    const std::vector<std::array<bool, kMarkers>>& present) {
  std::ostringstream text;
  const size_t count = frames.size();
  text << "PathFileType\t4\t(X/Y/Z)\t" << file << "\n"
       << "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n"
       << rate << '\t' << rate << '\t' << count << '\t' << kMarkers << "\tmm\t" << rate << "\t1\t" << count << "\n"
       << "Frame#\tTime";
  for (const JointMarker& marker : SmplJointMarkers()) text << '\t' << marker.smpl << "\t\t";
  text << "\n\t";
  for (int m = 1; m <= kMarkers; ++m) text << "\tX" << m << "\tY" << m << "\tZ" << m;
  text << "\n\n";
  char number[32];
  for (size_t t = 0; t < count; ++t) {
    std::snprintf(number, sizeof number, "%.6f", static_cast<double>(t) / rate);
    text << t + 1 << '\t' << number;
    for (int m = 0; m < kMarkers; ++m) {
      for (int axis = 0; axis < 3; ++axis) {
        text << '\t';
        if (!present[t][static_cast<size_t>(m)]) continue;
        std::snprintf(number, sizeof number, "%.3f", 1000.0 * frames[t][static_cast<size_t>(m * 3 + axis)]);
        text << number;
      }
    }
    text << '\n';
  }
  return text.str();
}

}  // namespace

std::vector<GeneratedTrial> GenerateArchive(const std::vector<SourceTrial>& sources, const std::string& output_dir,
                                            const ArchiveOptions& options, std::vector<std::string>* skipped) {
  std::vector<SourceJoints> usable;
  for (const SourceTrial& source : sources) {
    SourceJoints joints;
    if (LoadSource(source, joints)) {
      usable.push_back(std::move(joints));
    } else if (skipped) {
      skipped->push_back(source.path);
    }
  }
  if (usable.empty()) throw DataError(Location::InFile(output_dir), "no source trial has the joints the archive needs");
  const std::string captures = output_dir + "/captures";
  std::filesystem::create_directories(captures);
  std::vector<GeneratedTrial> trials;
  const double per_subject = options.hours * 3600.0 / options.subjects;
  const double wobble_period = 4.0;  // s
  for (int subject = 0; subject < options.subjects; ++subject) {
    SplitMix64 random(options.seed * 0x100000001b3ULL + static_cast<uint64_t>(subject));
    std::vector<size_t> order(usable.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    for (size_t i = order.size() - 1; i > 0; --i) std::swap(order[i], order[static_cast<size_t>(random.next() % (i + 1))]);
    char subject_name[16];
    std::snprintf(subject_name, sizeof subject_name, "s%02d", subject + 1);
    double filled = 0;
    for (size_t k = 0; filled < per_subject - 0.5 / options.rate; ++k) {
      const SourceJoints& source = usable[order[k % order.size()]];
      const double tempo = random.uniform(0.8, 1.2);
      const double amplitude = 0.1 * tempo * wobble_period / (2 * M_PI);  // keeps dt_src/dτ ≥ 0.9 r > 0
      const double phase = random.uniform(0, 2 * M_PI);
      const bool mirrored = random.uniform() < 0.5;
      std::vector<std::array<double, kMarkers * 3>> frames;
      for (int64_t j = 0;; ++j) {
        const double tau = static_cast<double>(j) / options.rate;
        if (filled + tau > per_subject + 1e-9) break;
        const double source_time = tempo * tau + amplitude * (std::sin(2 * M_PI * tau / wobble_period + phase) - std::sin(phase));
        if (source_time > source.duration()) break;
        const double position = source_time * source.rate;
        const size_t before = std::min(static_cast<size_t>(position), source.frames.size() - 2);
        const double weight = position - static_cast<double>(before);
        std::array<double, kMarkers * 3> frame{};
        for (int m = 0; m < kMarkers; ++m) {
          const int from = mirrored ? MirrorIndex(m) : m;
          for (int axis = 0; axis < 3; ++axis) {
            const size_t index = static_cast<size_t>(from * 3 + axis);
            double value = (1 - weight) * source.frames[before][index] + weight * source.frames[before + 1][index];
            if (mirrored && axis == 1) value = -value;
            frame[static_cast<size_t>(m * 3 + axis)] = value + 1e-3 * options.noise_mm * random.normal();
          }
        }
        frames.push_back(frame);
      }
      if (frames.size() < 2) break;
      // Interior gaps only: the first and last 31 frames stay whole so that gap filling can bridge every gap.
      std::vector<std::array<bool, kMarkers>> present(frames.size());
      for (auto& row : present) row.fill(true);
      for (int m = 0; m < kMarkers; ++m) {
        for (size_t t = 31; t + 31 < frames.size(); ++t) {
          if (random.uniform() >= options.gaps_per_second / options.rate) continue;
          const size_t length = 3 + static_cast<size_t>(random.next() % 28);
          for (size_t g = 0; g < length && t + g + 31 < frames.size(); ++g) present[t + g][static_cast<size_t>(m)] = false;
          t += length;
        }
      }
      GeneratedTrial trial;
      char id[32];
      std::snprintf(id, sizeof id, "%s_%03zu", subject_name, k + 1);
      trial.id = id;
      trial.subject = subject_name;
      trial.file = trial.id + ".trc";
      trial.source = source.trial->id;
      trial.motion_class = source.trial->motion_class;
      trial.style = source.trial->style;
      trial.mirrored = mirrored;
      trial.frames = static_cast<int64_t>(frames.size());
      trial.duration_s = static_cast<double>(frames.size() - 1) / options.rate;
      WriteFileAtomically(captures + "/" + trial.file, TrcText(trial.file, options.rate, frames, present));
      trials.push_back(trial);
      filled += static_cast<double>(frames.size()) / options.rate;
    }
  }
  return trials;
}

std::string ArchiveManifest(const std::vector<GeneratedTrial>& trials, const std::string& captures_root,
                            const ArchiveOptions& options) {
  std::ostringstream text;
  text << "# Generated by syn-archive from CMU BVH trials (time-warped, mirrored, marker noise and gaps): "
       << options.subjects << " subjects, " << options.hours << " h at " << options.rate << " Hz, seed "
       << options.seed << ".\n"
       << "# frames: " << [&] {
            int64_t frames = 0;
            for (const GeneratedTrial& trial : trials) frames += trial.frames;
            return frames;
          }() << "\n"
       << "name = \"archive\"\nversion = \"0.1.0\"\n"
       << "description = \"Synthetic scale-test archive from the CMU trials\"\n"
       << "root = \"" << captures_root << "\"\n"
       << "model = \"datasets/robots/unitree_g1/g1_29dof.urdf\"\n"
       << "robot_map = \"manifests/robots/g1.toml\"\n"
       << "markerset = \"manifests/markersets/humanml3d22.toml\"\n\n"
       << "[ingest]\nup_axis = \"z\"\nfill_gaps = 30\n\n"
       << "# Joint centres only: a stronger pull toward the reference stance keeps the arms' free swivel from\n"
       << "# drifting onto joint limits (syn-retarget --help).\n"
       << "[retarget]\nposture_scale = 10\n\n";
  if (options.paper_protocol) {
    text << "# The paper's protocol: metrics on a 1 kHz grid, 100 Monte-Carlo reconstructions per segment.\n"
         << "[evaluate]\neval_rate = 1000\nsamples = 100\n";
  } else {
    text << "# Throughput only: metrics at the capture rate, no Monte-Carlo (syn-archive --protocol throughput).\n"
         << "[evaluate]\neval_rate = " << options.rate << "\nsamples = 0\n";
  }
  for (const GeneratedTrial& trial : trials) {
    text << "\n[[trial]]\nid = \"" << trial.id << "\"\nsubject = \"" << trial.subject << "\"\nfile = \"" << trial.file
         << "\"\nmotion_class = \"" << trial.motion_class << "\"\nstyle = \"" << trial.style << "\"\n";
  }
  return text.str();
}

std::map<std::string, std::pair<std::string, std::string>> ReadCmuIndex(const std::string& path) {
  std::map<std::string, std::pair<std::string, std::string>> index;
  std::istringstream lines(ReadFileText(path));
  std::string line;
  std::getline(lines, line);  // header: subject,trial,file,motion_label,motion_class,dance_genre,...
  while (std::getline(lines, line)) {
    const std::vector<std::string> cells = SplitQuotedCsv(line);
    if (cells.size() >= 6) index[cells[1]] = {cells[4], cells[5]};
  }
  return index;
}

}  // namespace syn
