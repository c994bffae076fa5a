// `tmpc doctor` (runtime/doctor.hpp): each finding on fake procfs/sysfs trees, the
// latency verdict on injected runs, and one short real latency run.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>

#include <gtest/gtest.h>

#include "tmpc/runtime/doctor.hpp"

namespace tmpc {
namespace {

namespace fs = std::filesystem;

/// A fake root with procfs and sysfs files, removed at the end. Its name carries the
/// process id: ctest runs these tests as parallel processes, and two of them on one
/// shared folder removed each other's files (two tests failed at once, in 0.01 s).
struct FakeTree {
  fs::path root;
  explicit FakeTree(const std::string& name)
      : root(fs::path(::testing::TempDir()) / ("doctor_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(root);
    fs::create_directories(root / "proc");
    fs::create_directories(root / "sys");
  }
  FakeTree(const FakeTree&) = delete;
  FakeTree& operator=(const FakeTree&) = delete;
  FakeTree(FakeTree&& other) noexcept : root(std::move(other.root)) { other.root.clear(); }  // one owner removes it
  ~FakeTree() {
    std::error_code ignored;
    if (!root.empty()) fs::remove_all(root, ignored);
  }
  void write(const std::string& rel, const std::string& text) const {
    const fs::path p = root / rel;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
  }
  DoctorOptions options() const {
    DoctorOptions o;
    o.env.proc = (root / "proc").string();
    o.env.sys = (root / "sys").string();
    return o;
  }
};

const Finding& find(const std::vector<Finding>& fs, const std::string& check) {
  for (const Finding& f : fs) {
    if (f.check == check) return f;
  }
  static const Finding none{"(missing)", Severity::Fail, "", ""};
  ADD_FAILURE() << "no finding '" << check << "'";
  return none;
}

/// A board set up as the README's deployment guide says.
FakeTree good_board() {
  FakeTree t("good");
  t.write("proc/version", "Linux version 5.15.148-rt-tegra (gcc) #1 SMP PREEMPT_RT Tue\n");
  t.write("sys/kernel/realtime", "1\n");
  t.write("proc/sys/kernel/sched_rt_runtime_us", "-1\n");
  t.write("proc/sys/kernel/sched_rt_period_us", "1000000\n");
  for (int c = 0; c < 4; ++c) t.write("sys/devices/system/cpu/cpu" + std::to_string(c) + "/cpufreq/scaling_governor", "performance\n");
  t.write("sys/devices/system/cpu/isolated", "2-3\n");
  t.write("proc/self/limits",
          "Limit                     Soft Limit           Hard Limit           Units\n"
          "Max locked memory         unlimited            unlimited            bytes\n"
          "Max realtime priority     99                   99\n");
  return t;
}

TEST(Doctor, AWellSetUpBoardPassesEveryCheck) {
  FakeTree t = good_board();
  DoctorOptions o = t.options();
  o.cpu = 3;
  const std::vector<Finding> fs = check_host(o);
  for (const char* c : {"kernel", "rt throttling", "cpu governor", "isolated cpus", "memlock limit", "rtprio limit"}) {
    EXPECT_EQ(find(fs, c).severity, Severity::Ok) << c << ": " << find(fs, c).found;
    EXPECT_TRUE(find(fs, c).advice.empty()) << c;
  }
  EXPECT_EQ(find(fs, "kernel").found, "PREEMPT_RT");
  EXPECT_EQ(find(fs, "cpu governor").found, "performance on all 4 CPUs");
  EXPECT_TRUE(can_run(fs));
}

TEST(Doctor, EachMisconfigurationIsReportedWithWhatToDo) {
  FakeTree t("bad");
  t.write("proc/version", "Linux version 6.1.0-18-amd64 (gcc) #1 SMP PREEMPT_DYNAMIC Debian\n");
  t.write("proc/sys/kernel/sched_rt_runtime_us", "500000\n");
  t.write("proc/sys/kernel/sched_rt_period_us", "1000000\n");
  t.write("sys/devices/system/cpu/cpu0/cpufreq/scaling_governor", "performance\n");
  t.write("sys/devices/system/cpu/cpu1/cpufreq/scaling_governor", "schedutil\n");
  t.write("sys/devices/system/cpu/isolated", "\n");
  t.write("proc/self/limits",
          "Max locked memory         65536                65536                bytes\n"
          "Max realtime priority     0                    0\n");
  DoctorOptions o = t.options();
  o.rt_priority = 80;
  const std::vector<Finding> fs = check_host(o);
  const Finding& k = find(fs, "kernel");
  EXPECT_EQ(k.severity, Severity::Warn);
  EXPECT_EQ(k.found, "preemptible (PREEMPT), not PREEMPT_RT");
  EXPECT_NE(k.advice.find("PREEMPT_RT"), std::string::npos);
  const Finding& th = find(fs, "rt throttling");
  EXPECT_EQ(th.severity, Severity::Warn);
  EXPECT_NE(th.found.find("50 %"), std::string::npos) << th.found;
  EXPECT_NE(th.advice.find("sched_rt_runtime_us"), std::string::npos);
  const Finding& g = find(fs, "cpu governor");
  EXPECT_EQ(g.severity, Severity::Warn);
  EXPECT_NE(g.found.find("1 of 2 CPUs not at performance (cpu1: schedutil)"), std::string::npos) << g.found;
  EXPECT_NE(g.advice.find("jetson_clocks"), std::string::npos);
  const Finding& i = find(fs, "isolated cpus");
  EXPECT_EQ(i.severity, Severity::Warn);
  EXPECT_EQ(i.found, "none");
  EXPECT_NE(i.advice.find("isolcpus"), std::string::npos);
  const Finding& m = find(fs, "memlock limit");
  EXPECT_EQ(m.severity, Severity::Warn);
  EXPECT_NE(m.found.find("65536 bytes"), std::string::npos);
  EXPECT_NE(m.advice.find("LimitMEMLOCK=infinity"), std::string::npos);
  const Finding& p = find(fs, "rtprio limit");
  EXPECT_EQ(p.severity, Severity::Warn);
  EXPECT_NE(p.advice.find("LimitRTPRIO=80"), std::string::npos);
  EXPECT_TRUE(can_run(fs));  // warnings: it runs, with worse latency
  // Privileged: the limits do not apply.
  o.env.privileged = true;
  EXPECT_EQ(find(check_host(o), "rtprio limit").severity, Severity::Ok);
  // A loop pinned outside the isolated set.
  t.write("sys/devices/system/cpu/isolated", "2-3,5\n");
  o.cpu = 4;
  EXPECT_NE(find(check_host(o), "isolated cpus").found.find("CPU 4 is not among them"), std::string::npos);
  o.cpu = 5;
  EXPECT_EQ(find(check_host(o), "isolated cpus").severity, Severity::Ok);
}

TEST(Doctor, MissingFilesAreUnknownNotFailures) {
  FakeTree t("empty");
  const std::vector<Finding> fs = check_host(t.options());
  EXPECT_NE(find(fs, "kernel").found.find("unknown"), std::string::npos);
  EXPECT_EQ(find(fs, "rt throttling").severity, Severity::Info);
  EXPECT_EQ(find(fs, "cpu governor").severity, Severity::Info);
  EXPECT_EQ(find(fs, "isolated cpus").severity, Severity::Info);
  EXPECT_EQ(find(fs, "memlock limit").severity, Severity::Info);
  EXPECT_TRUE(can_run(fs));
}

TEST(Doctor, TheSerialDeviceMustExistBeACharacterDeviceAndHaveItsLatencyTimerAtOne) {
  FakeTree t = good_board();
  DoctorOptions o = t.options();
  o.port = (t.root / "no_such_tty").string();
  std::vector<Finding> fs = check_host(o);
  EXPECT_EQ(find(fs, "serial device").severity, Severity::Fail);
  EXPECT_NE(find(fs, "serial device").found.find("does not exist"), std::string::npos);
  EXPECT_FALSE(can_run(fs));
  t.write("plain_file", "x");
  o.port = (t.root / "plain_file").string();
  EXPECT_NE(find(check_host(o), "serial device").found.find("not a character device"), std::string::npos);
  // /dev/null stands in for a tty: a character device, readable and writable; its
  // (fake) USB latency timer at 16 ms, then at 1 ms.
  o.port = "/dev/null";
  t.write("sys/class/tty/null/device/latency_timer", "16\n");
  fs = check_host(o);
  EXPECT_EQ(find(fs, "serial device").severity, Severity::Ok);
  EXPECT_EQ(find(fs, "serial latency").severity, Severity::Warn);
  EXPECT_NE(find(fs, "serial latency").advice.find("echo 1 >"), std::string::npos);
  t.write("sys/class/tty/null/device/latency_timer", "1\n");
  EXPECT_EQ(find(check_host(o), "serial latency").severity, Severity::Ok);
}

TEST(Doctor, TheLatencyVerdictWeighsWakeUpAndSolveTimeAgainstTheBudget) {
  DoctorOptions o;  // 12 ms period, 0.8 of it: 9600 us
  o.solve_p99_us = 600.0;
  LatencyRun r;
  r.samples = 3000;
  r.realtime = true;
  r.p50_us = 10.0;
  r.p99_us = 40.0;
  r.max_us = 120.0;
  EXPECT_EQ(latency_verdict(r, o).severity, Severity::Ok);
  r.max_us = 9100.0;  // only the worst wake-up misses: rare fallback periods
  Finding f = latency_verdict(r, o);
  EXPECT_EQ(f.severity, Severity::Warn);
  EXPECT_NE(f.advice.find("worst wake-up"), std::string::npos);
  r.p99_us = 9001.0;  // 9001 + 600 > 9600: regular misses
  f = latency_verdict(r, o);
  EXPECT_EQ(f.severity, Severity::Fail);
  EXPECT_FALSE(can_run({f}));
  r.p99_us = 40.0;
  r.max_us = 120.0;
  r.realtime = false;
  r.note = "SCHED_FIFO 80: Operation not permitted";
  f = latency_verdict(r, o);
  EXPECT_EQ(f.severity, Severity::Warn);
  EXPECT_NE(f.found.find("not real-time"), std::string::npos);
  o.solve_p99_us = -1.0;  // unknown solve time: latency alone
  r.realtime = true;
  EXPECT_NE(latency_verdict(r, o).found.find("solve time not known"), std::string::npos);
  r.samples = 0;
  EXPECT_EQ(latency_verdict(r, o).severity, Severity::Fail);
}

TEST(Doctor, AShortLatencyRunMeasuresEveryWakeUp) {
  const LatencyRun r = measure_wakeup_latency(0.05, 0.001, 0, -1);  // no priority: anyone may run it
  EXPECT_EQ(r.samples, 50);
  EXPECT_LE(r.p50_us, r.p99_us);
  EXPECT_LE(r.p99_us, r.max_us);
  EXPECT_GE(r.p50_us, 0.0);
}

}  // namespace
}  // namespace tmpc
