// cms campbell: a speed sweep of the reduced model, the Campbell diagram
// (doc/user-guide.md, "cms campbell").
//
// Every spin rate is scaled from 0 to --max-factor times its nominal value
// (no re-projection: the reduced matrices are polynomials in the speeds,
// theory §11.5); modes are tracked across speeds by MAC (not by sorting,
// so crossings and veerings stay right), critical speeds are where a
// tracked frequency meets an engine order of the first spin rate, and the
// speed ranges where any mode is unstable are listed.
//
// Sample runs:
//   cms campbell
//   cms campbell drivers/scenes/spacecraft.yaml --steps=41 --max-factor=3 --orders=1,2 --plot
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <tuple>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "../DriverBoundary.hpp"
#include "Command.hpp"
#include "cms/analysis/ModalAnalysis.hpp"
#include "cms/io/AtomicFile.hpp"

namespace cms::drivers {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// M-weighted MAC of every pair (previous mode t, current mode j) of the
/// same coordinates: |a^H M b|^2 / (a^H M a  b^H M b), with two
/// applications of M and one reduction per call (q replicated on every rank
/// by the dense path, or this rank's rows by the sparse path). Collective.
std::vector<std::vector<double>> macMatrix(const synthesis::SynthesizedStructure& s, const CrsMatrix& M,
                                           const std::vector<eigen::GyroscopicMode>& prev,
                                           const std::vector<eigen::GyroscopicMode>& cur) {
  const auto map = M.getRowMap();
  const std::size_t nloc = map->getNodeNumElements(), P = prev.size(), C = cur.size();
  auto pack = [&](const std::vector<eigen::GyroscopicMode>& modes) {
    MultiVector X(map, std::max<std::size_t>(2 * modes.size(), 1));
    for (std::size_t j = 0; j < modes.size(); ++j) {
      const bool replicated = static_cast<long long>(modes[j].q.size()) == s.size();
      auto re = X.getDataNonConst(2 * j), im = X.getDataNonConst(2 * j + 1);
      for (std::size_t l = 0; l < nloc; ++l) {
        const std::size_t i = replicated ? static_cast<std::size_t>(map->getGlobalElement(static_cast<LocalOrdinal>(l))) : l;
        re[l] = modes[j].q[i].real(), im[l] = modes[j].q[i].imag();
      }
    }
    return X;
  };
  const MultiVector Xp = pack(prev), Xc = pack(cur);
  MultiVector MXp(map, Xp.getNumVectors()), MXc(map, Xc.getNumVectors());
  M.apply(Xp, MXp);
  M.apply(Xc, MXc);
  // Local sums: per pair (re, im) of a^H M b, then a^H M a per previous, b^H M b per current.
  std::vector<double> local(2 * P * C + P + C, 0.0), global(local.size(), 0.0);
  auto col = [](const MultiVector& X, std::size_t j) { return X.getData(j); };
  for (std::size_t t = 0; t < P; ++t) {
    const auto ar = col(Xp, 2 * t), ai = col(Xp, 2 * t + 1), Mar = col(MXp, 2 * t), Mai = col(MXp, 2 * t + 1);
    for (std::size_t l = 0; l < nloc; ++l) local[2 * P * C + t] += ar[l] * Mar[l] + ai[l] * Mai[l];
    for (std::size_t j = 0; j < C; ++j) {
      const auto Mbr = col(MXc, 2 * j), Mbi = col(MXc, 2 * j + 1);
      double re = 0, im = 0;
      // a^H M b = (ar.M br + ai.M bi) + i (ar.M bi - ai.M br)
      for (std::size_t l = 0; l < nloc; ++l) re += ar[l] * Mbr[l] + ai[l] * Mbi[l], im += ar[l] * Mbi[l] - ai[l] * Mbr[l];
      local[2 * (t * C + j)] = re, local[2 * (t * C + j) + 1] = im;
    }
  }
  for (std::size_t j = 0; j < C; ++j) {
    const auto br = col(Xc, 2 * j), bi = col(Xc, 2 * j + 1), Mbr = col(MXc, 2 * j), Mbi = col(MXc, 2 * j + 1);
    for (std::size_t l = 0; l < nloc; ++l) local[2 * P * C + P + j] += br[l] * Mbr[l] + bi[l] * Mbi[l];
  }
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
  std::vector<std::vector<double>> mac(P, std::vector<double>(C, 0.0));
  for (std::size_t t = 0; t < P; ++t)
    for (std::size_t j = 0; j < C; ++j) {
      const double aa = global[2 * P * C + t], bb = global[2 * P * C + P + j];
      const double n2 = global[2 * (t * C + j)] * global[2 * (t * C + j)] +
                        global[2 * (t * C + j) + 1] * global[2 * (t * C + j) + 1];
      mac[t][j] = aa > 0 && bb > 0 ? n2 / (aa * bb) : 0.0;
    }
  return mac;
}

}  // namespace

int campbell(int argc, char* argv[]) {
  // 1. Options and scene.
  Options options("campbell",
                  "A speed sweep of the reduced model (every spin rate scaled from 0 to --max-factor times its\n"
                  "nominal value, no re-projection): modes tracked by MAC, critical speeds, unstable ranges.");
  int steps = 21;
  double maxFactor = 2.0;
  std::string ordersText = "1";
  options.add("steps", &steps, "number of speeds (>= 2)");
  options.add("max-factor", &maxFactor, "top speed as a multiple of the nominal rates");
  options.add("orders", &ordersText, "engine orders of the first spin rate, comma-separated");
  options.plotOption();
  int code = ExitSuccess;
  const auto run = SceneRun::start(options, argc, argv, code);
  if (!run) return code;
  const auto& sc = run->scene;
  const bool root = run->root;
  const auto& outDir = run->outDir;
  const auto orders = positiveIntegers(ordersText, "--orders");
  auto comm = Teuchos::DefaultComm<int>::getComm();
  CMS_INPUT_CHECK(steps < 2, "--steps = " << steps << " must be at least 2");
  CMS_INPUT_CHECK(!(maxFactor > 0), "--max-factor = " << maxFactor << " must be positive");
  const auto structure = synthesis::AssembledStructure::assemble(sc.structure, comm);
  CMS_INPUT_CHECK(structure.speeds().empty(), sc.path << ": nothing spins in this scene: no Campbell diagram");
  const auto s = synthesis::SynthesizedStructure::synthesize(structure);
  const auto nominal = structure.nominalSpeeds();
  const auto M = s.system(std::vector<double>(nominal.size(), 0.0)).M;  // the same at every speed
  const auto t0 = Clock::now();
  // Tracks: frequency (Hz) and stability of one mode followed across speeds.
  struct Track {
    std::vector<double> hz;
    std::vector<std::string> stability, whirl;
    eigen::GyroscopicMode last;
  };
  // Whirl is reported for the first spinning A or R (its orbit about its axis).
  int spinning = -1;
  for (std::size_t k = 0; k < structure.numSubstructures() && spinning < 0; ++k)
    if (structure.substructure(k).kind != synthesis::SubstructureKind::Central && structure.substructure(k).spin)
      spinning = static_cast<int>(k);
  std::vector<Track> tracks;
  std::vector<double> factors;
  Outcome worst = kSuccess;  // breakdown (3) outranks not converged (4)
  std::string worstReason;
  std::vector<std::pair<double, double>> unstable;  // factor ranges
  for (int k = 0; k < steps; ++k) {
    const double f = maxFactor * k / (steps - 1);
    factors.push_back(f);
    std::vector<double> speeds(nominal);
    for (double& v : speeds) v *= f * sc.speedFactor;
    const auto m = s.solve(speeds, sc.solve);
    {
      const auto o = outcome(m.result.status);
      if (o.code != ExitSuccess && (worst.code == ExitSuccess || o.code == ExitNumericalError))
        worst = o, worstReason = condense(m.result.reason);
    }
    bool anyUnstable = false;
    for (const auto& md : m.result.modes)
      anyUnstable = anyUnstable || md.stability == eigen::Stability::Flutter ||
                    md.stability == eigen::Stability::Divergence;
    if (anyUnstable) {
      if (!unstable.empty() && unstable.back().second == factors[k > 0 ? k - 1 : 0] && k > 0) unstable.back().second = f;
      else unstable.push_back({f, f});
    }
    const auto& modes = m.result.modes;
    std::vector<std::string> wl(modes.size(), "");
    if (spinning >= 0)
      for (std::size_t j = 0; j < modes.size(); ++j)
        wl[j] = analysis::substructureWhirl(structure, s.expand(m, static_cast<int>(j)), static_cast<std::size_t>(spinning), modes[j]);
    if (tracks.empty()) {
      for (std::size_t j = 0; j < modes.size(); ++j)
        tracks.push_back({{modes[j].hz}, {toString(modes[j].stability)}, {wl[j]}, modes[j]});
      continue;
    }
    // Greedy assignment by decreasing MAC.
    std::vector<eigen::GyroscopicMode> last;
    for (const auto& tr : tracks) last.push_back(tr.last);
    const auto mac = macMatrix(s, *M, last, modes);
    std::vector<std::tuple<double, int, int>> pairs;
    for (std::size_t t = 0; t < tracks.size(); ++t)
      for (std::size_t j = 0; j < modes.size(); ++j)
        pairs.push_back({mac[t][j], static_cast<int>(t), static_cast<int>(j)});
    std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return std::get<0>(a) > std::get<0>(b); });
    std::vector<bool> trackDone(tracks.size(), false), modeDone(modes.size(), false);
    for (const auto& [mac, t, j] : pairs) {
      if (trackDone[t] || modeDone[j]) continue;
      trackDone[t] = modeDone[j] = true;
      tracks[t].hz.push_back(modes[j].hz);
      tracks[t].stability.push_back(toString(modes[j].stability));
      tracks[t].whirl.push_back(wl[j]);
      tracks[t].last = modes[j];
    }
    for (std::size_t t = 0; t < tracks.size(); ++t)
      if (!trackDone[t])
        tracks[t].hz.push_back(std::nan("")), tracks[t].stability.push_back("lost"), tracks[t].whirl.push_back("");
  }
  if (!root) return worst.code;
  const double ref = nominal.front() * sc.speedFactor;  // engine orders of the first spin rate
  std::cout << "[" << std::setprecision(3) << since(t0) << " s] " << steps << " speeds, " << s.size()
            << " coordinates, no re-projection\n\nfactor";
  for (std::size_t i = 0; i < nominal.size(); ++i) std::cout << "  " << structure.speeds()[i].name << "(rad/s)";
  for (std::size_t t = 0; t < tracks.size(); ++t) std::cout << "  track" << t + 1 << "(Hz)";
  std::cout << '\n';
  for (int k = 0; k < steps; ++k) {
    std::cout << std::setw(6) << std::setprecision(3) << factors[k];
    for (double v : nominal) std::cout << std::setw(14) << std::setprecision(5) << v * factors[k] * sc.speedFactor;
    for (const auto& tr : tracks)
      std::cout << std::setw(13) << std::setprecision(6) << tr.hz[k]
                << (tr.stability[k] == "stable" || tr.stability[k] == "rigid" || tr.stability[k] == "neutral" ? " " : "*");
    std::cout << '\n';
  }
  std::cout << "(* unstable or lost)\n\ncritical speeds of '" << structure.speeds().front().name << "' (rad/s):\n";
  for (int order : orders)
    for (std::size_t t = 0; t < tracks.size(); ++t)
      for (int k = 1; k < steps; ++k) {
        const double w0 = ref * factors[k - 1] * order, w1 = ref * factors[k] * order;
        const double a = tracks[t].hz[k - 1] * 2 * M_PI - w0, b = tracks[t].hz[k] * 2 * M_PI - w1;
        if (std::isfinite(a) && std::isfinite(b) && a * b < 0 && tracks[t].hz[k] > 0) {
          const double x = a / (a - b), speed = ref * (factors[k - 1] + x * (factors[k] - factors[k - 1]));
          std::cout << "  " << order << "X crosses track " << t + 1 << " at " << speed << " rad/s ("
                    << speed * 60 / (2 * M_PI) << " rpm)\n";
        }
      }
  for (const auto& [a, b] : unstable)
    std::cout << "unstable from factor " << a << " to " << b << " (" << ref * a << " to " << ref * b << " rad/s)\n";
  if (worst.code != ExitSuccess) {
    std::cerr << "cms: " << worst.message << " (exit " << worst.code << "): " << worstReason << "; no files written\n";
    return worst.code;
  }
  std::filesystem::create_directories(outDir);
  io::AtomicFile f(outDir / (sc.name + "-campbell.csv"));
  f.stream() << "factor";
  for (const auto& p : structure.speeds()) f.stream() << "," << p.name << "_rad_per_s";
  for (std::size_t t = 0; t < tracks.size(); ++t)
    f.stream() << ",track" << t + 1 << "_hz,track" << t + 1 << "_stability,track" << t + 1 << "_whirl";
  f.stream() << '\n';
  for (int k = 0; k < steps; ++k) {
    f.stream() << factors[k];
    for (double v : nominal) f.stream() << ',' << v * factors[k] * sc.speedFactor;
    for (const auto& tr : tracks) f.stream() << ',' << tr.hz[k] << ',' << tr.stability[k] << ',' << tr.whirl[k];
    f.stream() << '\n';
  }
  f.commit();
  std::cout << "\nwrote " << (outDir / (sc.name + "-campbell.csv")).string() << '\n';
  plot(options, "campbell", outDir / (sc.name + "-campbell.csv"));
  return ExitSuccess;
}

}  // namespace cms::drivers
