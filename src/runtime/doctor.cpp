// `tmpc doctor` (see doctor.hpp).
#include "tmpc/runtime/doctor.hpp"

#include <dirent.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "tmpc/runtime/percentiles.hpp"
#include "tmpc/runtime/realtime.hpp"

namespace tmpc {

const char* to_string(Severity s) {
  switch (s) {
    case Severity::Ok: return "ok";
    case Severity::Info: return "info";
    case Severity::Warn: return "warn";
    case Severity::Fail: return "FAIL";
  }
  return "?";
}

namespace {

/// The first line of a file, trimmed; false when it cannot be read.
bool read_line(const std::string& path, std::string& out) {
  std::ifstream in(path);
  if (!in) return false;
  std::getline(in, out);
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ' || out.back() == '\r')) out.pop_back();
  return true;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

Finding kernel(const DoctorEnvironment& e) {
  Finding f{"kernel", Severity::Warn, "", ""};
  std::string version, rt;
  read_line(e.proc + "/version", version);
  const bool rt_flag = read_line(e.sys + "/kernel/realtime", rt) && rt == "1";
  if (rt_flag || version.find("PREEMPT_RT") != std::string::npos) {
    f.severity = Severity::Ok;
    f.found = "PREEMPT_RT";
    return f;
  }
  const bool preempt = version.find(" PREEMPT") != std::string::npos;  // PREEMPT, PREEMPT_DYNAMIC
  f.found = version.empty() ? "unknown (no " + e.proc + "/version)" : (preempt ? "preemptible (PREEMPT), not PREEMPT_RT" : "not preemptible");
  f.advice = "install a PREEMPT_RT kernel (on a Jetson, the real-time kernel of its JetPack/L4T release); a "
             "low-latency kernel bounds the typical wake-up, not the worst";
  return f;
}

Finding throttling(const DoctorEnvironment& e) {
  Finding f{"rt throttling", Severity::Info, "", ""};
  std::string runtime, period;
  if (!read_line(e.proc + "/sys/kernel/sched_rt_runtime_us", runtime)) {
    f.found = "unknown (no sched_rt_runtime_us)";
    return f;
  }
  read_line(e.proc + "/sys/kernel/sched_rt_period_us", period);
  const long r = std::atol(runtime.c_str()), p = period.empty() ? 1000000 : std::atol(period.c_str());
  if (r < 0) {
    f.severity = Severity::Ok;
    f.found = "off (sched_rt_runtime_us = -1): real-time threads are never throttled";
    return f;
  }
  const double share = p > 0 ? static_cast<double>(r) / static_cast<double>(p) : 0.0;
  f.found = "real-time threads may use " + fmt("%.0f", 100.0 * share) + " % of each " + std::to_string(p) + " us";
  if (share >= 0.9) {
    f.severity = Severity::Ok;  // a periodic loop using a fraction of its period never reaches it
  } else {
    f.severity = Severity::Warn;
    f.advice = "echo 950000 > /proc/sys/kernel/sched_rt_runtime_us (or -1: never throttle)";
  }
  return f;
}

Finding governors(const DoctorEnvironment& e) {
  Finding f{"cpu governor", Severity::Info, "", ""};
  const std::string dir = e.sys + "/devices/system/cpu";
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) {
    f.found = "unknown (no " + dir + ")";
    return f;
  }
  std::vector<std::string> slow;
  int cpus = 0;
  while (const dirent* ent = ::readdir(d)) {
    const std::string name = ent->d_name;
    if (name.size() < 4 || name.compare(0, 3, "cpu") != 0 || name.find_first_not_of("0123456789", 3) != std::string::npos) continue;
    std::string g;
    if (!read_line(dir + "/" + name + "/cpufreq/scaling_governor", g)) continue;
    ++cpus;
    if (g != "performance") slow.push_back(name + ": " + g);
  }
  ::closedir(d);
  if (cpus == 0) {
    f.found = "no cpufreq (a fixed clock, or a virtual machine)";
    return f;
  }
  std::sort(slow.begin(), slow.end());
  if (slow.empty()) {
    f.severity = Severity::Ok;
    f.found = "performance on all " + std::to_string(cpus) + " CPUs";
    return f;
  }
  f.severity = Severity::Warn;
  f.found = std::to_string(slow.size()) + " of " + std::to_string(cpus) + " CPUs not at performance (" + slow.front() +
            (slow.size() > 1 ? ", ..." : "") + ")";
  f.advice = "set the governor to performance (cpupower frequency-set -g performance; on a Jetson: sudo jetson_clocks)";
  return f;
}

/// CPU list "1-3,5" -> membership of `cpu`.
bool in_cpu_list(const std::string& list, int cpu) {
  std::stringstream ss(list);
  for (std::string part; std::getline(ss, part, ',');) {
    if (part.empty()) continue;
    const std::size_t dash = part.find('-');
    const int lo = std::atoi(part.c_str()), hi = dash == std::string::npos ? lo : std::atoi(part.c_str() + dash + 1);
    if (cpu >= lo && cpu <= hi) return true;
  }
  return false;
}

Finding isolated(const DoctorEnvironment& e, int cpu) {
  Finding f{"isolated cpus", Severity::Warn, "", ""};
  std::string list;
  if (!read_line(e.sys + "/devices/system/cpu/isolated", list)) {
    f.severity = Severity::Info;
    f.found = "unknown (no isolated list)";
    return f;
  }
  if (list.empty()) {
    f.found = "none";
    f.advice = "isolate a CPU for the loop (kernel command line: isolcpus=N nohz_full=N rcu_nocbs=N) and pass --cpu N";
    return f;
  }
  if (cpu >= 0 && !in_cpu_list(list, cpu)) {
    f.found = list + "; the loop's CPU " + std::to_string(cpu) + " is not among them";
    f.advice = "pin the loop to an isolated CPU (--cpu)";
    return f;
  }
  f.severity = cpu >= 0 ? Severity::Ok : Severity::Warn;
  f.found = list + (cpu >= 0 ? "; the loop on CPU " + std::to_string(cpu) : "; the loop is not pinned");
  if (cpu < 0) f.advice = "pin the loop to one of them (--cpu)";
  return f;
}

/// The soft limit of a /proc/PID/limits line ("Max locked memory  65536  65536  bytes").
bool limit(const std::string& limits_path, const std::string& name, std::string& soft) {
  std::ifstream in(limits_path);
  for (std::string line; std::getline(in, line);) {
    if (line.compare(0, name.size(), name) != 0) continue;
    std::stringstream ss(line.substr(name.size()));
    ss >> soft;
    return !soft.empty();
  }
  return false;
}

std::vector<Finding> limits(const DoctorOptions& o) {
  const DoctorEnvironment& e = o.env;
  Finding mem{"memlock limit", Severity::Warn, "", ""}, prio{"rtprio limit", Severity::Warn, "", ""};
  std::string m, p;
  const std::string path = e.proc + "/self/limits";
  if (e.privileged) {
    mem = {"memlock limit", Severity::Ok, "privileged (root): mlockall is not limited", ""};
    prio = {"rtprio limit", Severity::Ok, "privileged (root): any SCHED_FIFO priority", ""};
    return {mem, prio};
  }
  if (!limit(path, "Max locked memory", m)) {
    mem = {"memlock limit", Severity::Info, "unknown (no " + path + ")", ""};
  } else if (m == "unlimited" || std::atof(m.c_str()) >= 512.0 * 1024 * 1024) {
    mem.severity = Severity::Ok;
    mem.found = m == "unlimited" ? "unlimited" : m + " bytes";
  } else {
    mem.found = m + " bytes: mlockall of the controller (tens of MB, more with CUDA) fails";
    mem.advice = "LimitMEMLOCK=infinity in the service (or memlock unlimited in /etc/security/limits.conf)";
  }
  if (!limit(path, "Max realtime priority", p)) {
    prio = {"rtprio limit", Severity::Info, "unknown (no " + path + ")", ""};
  } else if (p == "unlimited" || std::atoi(p.c_str()) >= o.rt_priority) {
    prio.severity = Severity::Ok;
    prio.found = p + " (the loop asks " + std::to_string(o.rt_priority) + ")";
  } else {
    prio.found = p + ": SCHED_FIFO " + std::to_string(o.rt_priority) + " will be refused (the loop runs, unprotected)";
    prio.advice = "LimitRTPRIO=" + std::to_string(o.rt_priority) + " in the service (or rtprio in limits.conf), or run as root";
  }
  return {mem, prio};
}

std::vector<Finding> serial(const DoctorOptions& o) {
  std::vector<Finding> out;
  Finding f{"serial device", Severity::Fail, "", ""};
  struct stat st {};
  if (::stat(o.port.c_str(), &st) != 0) {
    f.found = o.port + " does not exist";
    f.advice = "check the cable and the device name (ls /dev/ttyTHS* /dev/ttyUSB* /dev/ttyACM*)";
    return {f};
  }
  if (!S_ISCHR(st.st_mode)) {
    f.found = o.port + " is not a character device";
    f.advice = "give the serial device (e.g. /dev/ttyTHS0 on a Jetson's UART)";
    return {f};
  }
  if (::access(o.port.c_str(), R_OK | W_OK) != 0) {
    f.found = o.port + ": no read and write permission for this user";
    f.advice = "add the user to the device's group (usually dialout: sudo usermod -aG dialout USER) or run the service as it";
    return {f};
  }
  f.severity = Severity::Ok;
  f.found = o.port + ": a character device, readable and writable";
  out.push_back(f);
  // A USB-serial adapter (FTDI) batches bytes for latency_timer ms: 16 by default.
  const std::string name = o.port.substr(o.port.find_last_of('/') + 1);
  std::string timer;
  Finding l{"serial latency", Severity::Info, "", ""};
  if (read_line(o.env.sys + "/class/tty/" + name + "/device/latency_timer", timer)) {
    const int ms = std::atoi(timer.c_str());
    l.found = "USB adapter latency timer " + timer + " ms";
    if (ms <= 1) {
      l.severity = Severity::Ok;
    } else {
      l.severity = Severity::Warn;
      l.advice = "echo 1 > /sys/class/tty/" + name + "/device/latency_timer (a udev rule makes it stick): a state frame "
                 "otherwise waits up to " + timer + " ms";
    }
  } else {
    l.found = "no latency timer (not a USB-serial adapter); the low_latency flag: setserial " + o.port + " low_latency";
  }
  out.push_back(l);
  return out;
}

}  // namespace

std::vector<Finding> check_host(const DoctorOptions& o) {
  std::vector<Finding> out = {kernel(o.env), throttling(o.env), governors(o.env), isolated(o.env, o.cpu)};
  for (Finding& f : limits(o)) out.push_back(std::move(f));
  if (!o.port.empty()) {
    for (Finding& f : serial(o)) out.push_back(std::move(f));
  }
  return out;
}

LatencyRun measure_wakeup_latency(double seconds, double interval_s, int priority, int cpu) {
  LatencyRun r;
  std::vector<double> lat;
  const long n = std::max(1L, static_cast<long>(seconds / interval_s + 0.5));
  lat.reserve(static_cast<std::size_t>(n));
  std::thread t([&] {
    RealTimeSettings s;
    s.priority = priority;
    s.cpu = cpu;
    s.lock_memory = false;  // the process's, not this run's
    s.prefault_stack = 64 * 1024;
    const RealTimeReport rep = apply_realtime(s);
    r.realtime = rep.scheduler;
    for (const std::string& m : rep.not_set) r.note += (r.note.empty() ? "" : "; ") + m;
    const long step = static_cast<long>(interval_s * 1e9);
    timespec next {};
    clock_gettime(CLOCK_MONOTONIC, &next);
    for (long k = 0; k < n; ++k) {
      next = add_ns(next, step);
      clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
      timespec now {};
      clock_gettime(CLOCK_MONOTONIC, &now);
      lat.push_back(std::max(0.0, diff_us(now, next)));
    }
  });
  t.join();
  r.samples = static_cast<int>(lat.size());
  r.p50_us = percentile(lat, 0.5);
  r.p99_us = percentile(lat, 0.99);
  r.max_us = percentile(lat, 1.0);
  return r;
}

Finding latency_verdict(const LatencyRun& r, const DoctorOptions& o) {
  Finding f{"wake-up latency", Severity::Ok, "", ""};
  const double budget = o.deadline_fraction * o.period_s * 1e6, solve = std::max(0.0, o.solve_p99_us);
  f.found = std::to_string(r.samples) + " wake-ups: p50 " + fmt("%.0f", r.p50_us) + " us, p99 " + fmt("%.0f", r.p99_us) +
            " us, max " + fmt("%.0f", r.max_us) + " us" + (r.realtime ? " at SCHED_FIFO" : " (not real-time: " + r.note + ")") +
            "; the optimizer's budget " + fmt("%.0f", budget) + " us" +
            (o.solve_p99_us >= 0.0 ? ", solve p99 " + fmt("%.0f", o.solve_p99_us) + " us" : ", solve time not known (--controller)");
  if (r.samples == 0 || r.p99_us + solve > budget) {
    f.severity = Severity::Fail;
    f.advice = "the loop would miss its deadline regularly (the LQR fallback flies those periods): fix the findings "
               "above (PREEMPT_RT, an isolated CPU, the governor) or a faster solver";
  } else if (r.max_us + solve > budget) {
    f.severity = Severity::Warn;
    f.advice = "the worst wake-up misses the deadline (a late period flies the LQR fallback): see the findings above";
  } else if (!r.realtime) {
    f.severity = Severity::Warn;
    f.advice = "measured without SCHED_FIFO: run the doctor with the service's privileges";
  }
  return f;
}

bool can_run(const std::vector<Finding>& findings) {
  return std::none_of(findings.begin(), findings.end(), [](const Finding& f) { return f.severity == Severity::Fail; });
}

}  // namespace tmpc
