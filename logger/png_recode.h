#pragma once
// Lossless compression of camera messages for the logger: the MONO8 images of an encoded
// stereo_frame_t become PNG (every other field kept), which the tracker decodes as it does a
// PNG-encoded camera. About 2-3x smaller on real images, at some CPU.
#include <cstdint>
#include <string>
#include <vector>

namespace hs {

// Re-encodes `data` in place. False, with `data` untouched and the reason in `error`, when it is
// not a valid stereo_frame_t (the logger then records it as received).
bool recode_stereo_png(std::vector<uint8_t>* data, std::string* error);

}  // namespace hs
