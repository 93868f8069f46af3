#include "drivers/imu/iio_device.h"

#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "common/core/error.h"

namespace hs {
namespace {

std::optional<std::string> read_attr(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::string value;
  std::getline(in, value);
  return value;
}

void write_attr(const std::string& path, const std::string& value, const std::string& what) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0)
    throw std::runtime_error("cannot set " + what + " (" + path + "): " + std::strerror(errno));
  const ssize_t n = ::write(fd, value.data(), value.size());
  const int err = errno;
  ::close(fd);
  if (n != static_cast<ssize_t>(value.size()))
    throw std::runtime_error("cannot set " + what + " to '" + value + "' (" + path +
                             "): " + std::strerror(err));
}

bool exists(const std::string& path) {
  return ::access(path.c_str(), F_OK) == 0;
}

std::vector<std::string> list_dir(const std::string& dir) {
  std::vector<std::string> names;
  if (DIR* d = ::opendir(dir.c_str())) {
    while (const dirent* e = ::readdir(d))
      if (e->d_name[0] != '.') names.emplace_back(e->d_name);
    ::closedir(d);
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string find_device(const std::string& root, const std::string& device) {
  std::string names;
  for (const std::string& entry : list_dir(root)) {
    if (entry.rfind("iio:device", 0) != 0) continue;
    const std::string name = read_attr(root + "/" + entry + "/name").value_or("");
    if (entry == device || name == device) return entry;
    names += (names.empty() ? "" : ", ") + entry + " (" + name + ")";
  }
  throw std::runtime_error("no IIO device '" + device + "' in " + root +
                           (names.empty() ? " (none there)" : "; there are: " + names));
}

// A channel's scale or offset: its own attribute, else the one shared by its type
// (in_accel_x -> in_accel_scale), else `fallback`.
double channel_attr(const std::string& dir, const std::string& channel, const std::string& attr,
                    double fallback) {
  const size_t type_end = channel.find_first_not_of("abcdefghijklmnopqrstuvwxyz", 3);
  for (const std::string& base : {channel, channel.substr(0, type_end)}) {
    if (const auto text = read_attr(dir + "/" + base + "_" + attr)) {
      try {
        return std::stod(*text);
      } catch (const std::exception&) {
        throw InputError(dir + "/" + base + "_" + attr + ": '" + *text + "' is not a number");
      }
    }
  }
  return fallback;
}

std::string find_trigger_dir(const std::string& root, const std::string& trigger) {
  for (const std::string& entry : list_dir(root))
    if (entry.rfind("trigger", 0) == 0 && read_attr(root + "/" + entry + "/name") == trigger)
      return root + "/" + entry;
  return "";
}

}  // namespace

IioDevice::IioDevice(const IioOptions& o, IioPart part)
    : has_accel_(part != IioPart::kGyro), has_gyro_(part != IioPart::kAccel) {
  const bool gyro_device = part == IioPart::kGyro;
  const std::string& trigger = gyro_device ? o.gyro_trigger : o.trigger;
  const double rate_hz = gyro_device ? o.gyro_sampling_frequency_hz : o.sampling_frequency_hz;
  const std::string entry = find_device(o.sysfs_root, gyro_device ? o.gyro_device : o.device);
  dir_ = o.sysfs_root + "/" + entry;
  name_ = entry + " (" + read_attr(dir_ + "/name").value_or("?") + ")";
  const std::vector<std::string> available = scan_elements();
  const std::vector<std::string> wanted = wanted_channels(o, available);

  // Busy: the kernel lets one reader open the buffer.
  const std::string dev = o.dev_root + "/" + entry;
  fd_ = ::open(dev.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0)
    throw std::runtime_error("cannot open " + dev + ": " + std::strerror(errno) +
                             (errno == EBUSY ? " (another reader has it)" : ""));
  try {
    // A buffer left enabled by a reader that died is stopped before the settings change.
    write_attr(dir_ + "/buffer/enable", "0", "the buffer");
    if (exists(dir_ + "/current_timestamp_clock"))
      write_attr(dir_ + "/current_timestamp_clock", "monotonic", "the timestamp clock");
    set_trigger_and_rate(o.sysfs_root, trigger, rate_hz);
    for (const std::string& a : available)
      write_attr(dir_ + "/scan_elements/" + a + "_en",
                 std::find(wanted.begin(), wanted.end(), a) == wanted.end() ? "0" : "1",
                 "scan element " + a);
    read_layout(o, wanted);
    if (exists(dir_ + "/buffer/length"))
      write_attr(dir_ + "/buffer/length", std::to_string(o.buffer_length), "the buffer length");
    try {
      write_attr(dir_ + "/buffer/enable", "1", "the buffer");
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(std::string(e.what()) +
                               (trigger.empty() ? " (no trigger given: set its trigger?)" : ""));
    }
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

std::vector<std::string> IioDevice::scan_elements() const {
  std::vector<std::string> available;
  for (const std::string& f : list_dir(dir_ + "/scan_elements"))
    if (f.size() > 3 && f.compare(f.size() - 3, 3, "_en") == 0)
      available.push_back(f.substr(0, f.size() - 3));
  if (available.empty())
    throw std::runtime_error(name_ + " has no scan elements: not a buffered IIO device");
  return available;
}

std::vector<std::string> IioDevice::wanted_channels(
    const IioOptions& o, const std::vector<std::string>& available) const {
  // Each configured channel once, then the kernel's timestamp.
  std::vector<std::string> wanted;
  for (const auto* axes : {has_accel_ ? &o.accel : nullptr, has_gyro_ ? &o.gyro : nullptr})
    for (size_t i = 0; axes && i < axes->size(); ++i)
      if (std::find(wanted.begin(), wanted.end(), (*axes)[i]) == wanted.end())
        wanted.push_back((*axes)[i]);
  wanted.push_back("in_timestamp");
  std::string all;
  for (const std::string& a : available) all += (all.empty() ? "" : ", ") + a;
  for (const std::string& c : wanted)
    if (std::find(available.begin(), available.end(), c) == available.end())
      throw InputError(name_ + " has no scan element '" + c + "'" +
                       (c == "in_timestamp" ? " (samples need the kernel's timestamps)" : "") +
                       "; its scan elements: " + all);
  return wanted;
}

void IioDevice::set_trigger_and_rate(const std::string& sysfs_root, const std::string& trigger,
                                     double rate_hz) const {
  if (!trigger.empty()) {
    write_attr(dir_ + "/trigger/current_trigger", trigger, "the trigger");
    if (read_attr(dir_ + "/trigger/current_trigger") != trigger)
      throw std::runtime_error(name_ + " did not take trigger '" + trigger + "'");
  }
  if (rate_hz <= 0) return;
  // A software trigger (hrtimer, sysfs) sets the rate itself; else the device does.
  const std::string trigger_dir = trigger.empty() ? "" : find_trigger_dir(sysfs_root, trigger);
  std::string target;
  for (const std::string& t : {trigger_dir.empty() ? "" : trigger_dir + "/sampling_frequency",
                               dir_ + "/sampling_frequency", dir_ + "/in_sampling_frequency"})
    if (target.empty() && !t.empty() && exists(t)) target = t;
  if (target.empty())
    throw std::runtime_error(name_ + " and its trigger have no sampling_frequency to set");
  std::ostringstream hz;
  hz << rate_hz;
  write_attr(target, hz.str(), "the sampling frequency");
}

void IioDevice::read_layout(const IioOptions& o, const std::vector<std::string>& wanted) {
  const std::string scan_dir = dir_ + "/scan_elements";
  for (const std::string& c : wanted) {
    IioScanChannel ch;
    ch.name = c;
    const auto index = read_attr(scan_dir + "/" + c + "_index");
    const auto type = read_attr(scan_dir + "/" + c + "_type");
    if (!index || !type)
      throw InputError(name_ + ": scan element " + c + " lacks its index or type");
    try {
      ch.index = std::stoi(*index);
    } catch (const std::exception&) {
      throw InputError(scan_dir + "/" + c + "_index: '" + *index + "' is not a number");
    }
    ch.type = parse_iio_scan_type(*type);
    channels_.push_back(ch);
  }
  scan_bytes_ = layout_iio_scan(channels_);
  const auto position = [&](const std::string& c) {
    return static_cast<size_t>(
        std::find_if(channels_.begin(), channels_.end(),
                     [&](const IioScanChannel& ch) { return ch.name == c; }) -
        channels_.begin());
  };
  timestamp_ = position("in_timestamp");
  const IioScanType& ts = channels_[timestamp_].type;
  if (ts.storagebits != 64 || !ts.is_signed)
    throw InputError(name_ + ": in_timestamp is not a signed 64-bit value");
  const auto axis = [&](const std::string& c) {
    return Axis{position(c), channel_attr(dir_, c, "scale", 1), channel_attr(dir_, c, "offset", 0)};
  };
  for (int i = 0; i < 3; ++i) {
    if (has_accel_) accel_[i] = axis(o.accel[i]);
    if (has_gyro_) gyro_[i] = axis(o.gyro[i]);
  }
}

IioDevice::~IioDevice() {
  try {
    write_attr(dir_ + "/buffer/enable", "0", "the buffer");
  } catch (const std::exception&) {
    // The device is gone: nothing to stop.
  }
  ::close(fd_);
}

IioDevice::ReadStatus IioDevice::read(int timeout_ms, std::vector<ImuSample>* samples) {
  pollfd p{fd_, POLLIN, 0};
  if (::poll(&p, 1, timeout_ms) < 0 && errno != EINTR) return ReadStatus::kLost;
  // Read even when poll saw nothing: a removed device polls as idle and reads ENODEV.
  uint8_t buffer[4096];
  const ssize_t n = ::read(fd_, buffer, sizeof(buffer) / scan_bytes_ * scan_bytes_);
  if (n < 0) return errno == EAGAIN || errno == EINTR ? ReadStatus::kTimeout : ReadStatus::kLost;
  if (n == 0) return ReadStatus::kLost;  // end of file: a pipe's writer gone (tests)
  carry_.insert(carry_.end(), buffer, buffer + n);
  size_t used = 0;
  for (; carry_.size() - used >= scan_bytes_; used += scan_bytes_) {
    const uint8_t* scan = carry_.data() + used;
    ImuSample s;
    s.t_ns = decode_iio_value(scan, channels_[timestamp_]);
    const auto value = [&](const Axis& a) {
      return (static_cast<double>(decode_iio_value(scan, channels_[a.channel])) + a.offset) *
             a.scale;
    };
    for (int i = 0; i < 3; ++i) {
      if (has_accel_) s.accel[i] = value(accel_[i]);
      if (has_gyro_) s.gyro[i] = value(gyro_[i]);
    }
    samples->push_back(s);
  }
  carry_.erase(carry_.begin(), carry_.begin() + static_cast<std::ptrdiff_t>(used));
  return ReadStatus::kData;
}

}  // namespace hs
