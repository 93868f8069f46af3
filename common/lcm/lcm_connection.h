#pragma once
// Creating LCM instances for tools and processes, with the checks that udpm on loopback needs
// (see README: a multicast route on lo and net.core.rmem_max of 16 MiB).
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>

namespace hs {

// Loopback-only multicast with a receive buffer that holds many raw stereo pairs (~720 kB each).
constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=16777216";
constexpr long long kWantedReceiveBuffer = 16 * 1024 * 1024;

// $LCM_DEFAULT_URL when set, else kDefaultLcmUrl.
std::string default_lcm_url();

// Throws InputError naming the URL (with the usual causes) if LCM cannot start.
std::unique_ptr<lcm::LCM> connect_lcm(const std::string& url);

// net.core.rmem_max in bytes, or -1 if it cannot be read.
long long read_rmem_max();

// For a udpm:// URL, a warning when the kernel caps its receive buffer below what large
// messages need (the URL's recv_buf_size, or 16 MiB); empty when fine or not udpm.
std::string receive_buffer_warning(const std::string& url);

}  // namespace hs
