// The native `.sdcb` model file: a magic number, a format version, then
// chunks (4-byte type, u64 payload length, payload, CRC-32), so the format
// can grow: readers skip chunk types they do not know. The byte layout,
// versioning rules and limits are specified in docs/FORMAT.md.
//
// Versions 2 and 3 (written here) store the knots and the control points, not
// the configurations: the reader recomputes them from the knots
// (ComputeDelaunayConfigurations: exact predicates, symbolic perturbation,
// deterministic) and checks them against a stored hash. Arrays are stored as
// byte planes deflated with zlib; the sphere parameters only on request;
// control points optionally quantized with a stated error bound
// (io/sdcb/control_point_quantization.h). Version 1 files still read.
// Version 4 (io/sdcb/sdcb_model_file.cpp) stores a Model of parts, each
// spline in those chunks, with its name and trim loops.
//
// Writing is deterministic (same model and options, same bytes, for one zlib
// build: fixed chunk order, no timestamps) and atomic (a temporary file
// renamed into place). Reading checks every length against the bytes
// present before allocating (inflated sizes are declared, bounded by
// deflate's maximum ratio and never exceeded), every CRC, every index and
// every number, and returns kCorruptFile naming the problem instead of
// crashing or returning a partial model.
#ifndef SDCB_IO_SDCB_SDCB_FILE_H_
#define SDCB_IO_SDCB_SDCB_FILE_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/model.h"
#include "sdcb/core/spline/spline_model.h"
#include "sdcb/io/sdcb/control_point_quantization.h"

namespace sdcb {

// The newest version this code writes and reads (it reads 1 to 4). A model
// of one closed unnamed part is written as version 3 when the file uses a
// chunk version 3 added (QKNT, PCTL: knots on a grid, quantized control
// points), else version 2, which older readers read too. Version 4 holds a
// Model (core/spline/model.h) of several parts, names or trims; it is
// written only for such a model.
constexpr uint32_t kSdcbFormatVersion = 4;

// A version 4 part's name: UTF-8, at most this many bytes.
constexpr size_t kMaxPartNameBytes = 1024;

// The 8 bytes every .sdcb file starts with: 0x89 "SDCB" CR LF 0x1A. The
// non-ASCII first byte and the CR LF pair detect 7-bit and text-mode
// (newline-converting) transfers, 0x1A stops `type` on DOS.
inline constexpr char kSdcbMagic[8] = {'\x89', 'S',    'D',    'C',
                                       'B',    '\x0D', '\x0A', '\x1A'};

// The octahedral knot grid (FitOptions::knot_grid_bits) `sdcb fit
// --quantize` snaps to: the knots then take 4 bytes each, not 24.
constexpr int kQuantizedFitKnotGridBits = 16;

// SdcbWriteOptions::quantize_bits: choose the bits from the fit's error.
constexpr int kQuantizeBitsAuto = -1;

struct SdcbWriteOptions {
  // Store model.parameters when the model has them; false drops them (the
  // file then reads back without parameters).
  bool store_parameters = true;
  // 0: control points stored exactly (lossless). kMinQuantizationBits..
  // kMaxQuantizationBits: quantized to that many bits per coordinate; the
  // file states the error bound (io/sdcb/control_point_quantization.h).
  // kQuantizeBitsAuto: the coarsest grid of cubic cells whose bound is at
  // most quantize_fraction_of_rms x the fit's rms (model.statistics'
  // final_result.rmse_percent, which must be > 0;
  // QuantizeControlPointsWithin).
  int quantize_bits = 0;
  double quantize_fraction_of_rms = 0.5;
  // 3: knots on the fit's grid (FitOptions::knot_grid_bits) as grid codes
  // (QKNT) and quantized control points predicted and range-coded (PCTL).
  // 2: as version 2 wrote them (KNOT, QCTL), for readers of version 2.
  int format_version = 3;
};

// How one part's spline is stored.
struct SdcbPartStorage {
  // bits == 0 for exact control points (and for every version 1 file).
  ControlPointQuantization quantization;
  // Bits of the grid the knots are stored on (QKNT); 0: stored as doubles.
  int knot_grid_bits = 0;
};

// What a file says about itself beyond the model.
struct SdcbFileInfo {
  uint32_t format_version = 0;
  uint64_t file_bytes = 0;
  // Part 1's storage (the only part of a version 1 to 3 file).
  ControlPointQuantization quantization;
  int knot_grid_bits = 0;
  // One entry per part, in order (one for versions 1 to 3).
  std::vector<SdcbPartStorage> parts;
};

// The complete file contents (format version 2 or 3) for `model`. Fails with
// kInvalidArgument if ValidateSplineModel(model) fails or the model's
// configurations are not ComputeDelaunayConfigurations(knots, degree) (an
// invalid model is never written), or if `options` or the quantization is
// invalid (QuantizeControlPoints). `info`, if not null, receives the
// version, size and quantization of the result.
StatusOr<std::string> SerializeSdcb(const SplineModel& model,
                                    const SdcbWriteOptions& options = {},
                                    SdcbFileInfo* info = nullptr);

// Parses complete file contents (format version 1 to 4; a version 4 file
// only if it holds one untrimmed part, read without its name and the
// model's source: otherwise
// kUnsupported, "the file holds 3 parts; ..."). Any malformation
// (bad magic, newer version, truncation, bad CRC, missing or duplicate
// required chunk, sizes that do not match the declared counts, a corrupt
// zlib stream, an index out of range, a non-finite number, configurations
// that do not match the stored hash, a model that fails ValidateSplineModel)
// gives kCorruptFile (kUnsupported for a newer format version) with a message
// naming the problem; the caller adds the file name. `info`, if not null,
// receives what the file says about itself.
StatusOr<SplineModel> ParseSdcb(std::string_view bytes,
                                SdcbFileInfo* info = nullptr);

// SerializeSdcb(model, options, info) written to `path` atomically: on
// failure `path` is left untouched. Messages start with `path`.
Status WriteSdcbFile(const SplineModel& model, const std::string& path,
                     const SdcbWriteOptions& options = {},
                     SdcbFileInfo* info = nullptr);

// Reads and parses `path`. kIoError if it cannot be read; otherwise as
// ParseSdcb. Messages start with `path`.
StatusOr<SplineModel> ReadSdcbFile(const std::string& path,
                                   SdcbFileInfo* info = nullptr);

// --- Models of parts (io/sdcb/sdcb_model_file.cpp) ---------------------------

// The complete file contents for `model`. A model of one closed unnamed part
// whose source is its spline's gives exactly SerializeSdcb(part's spline,
// options, info). Any other model gives a version 4 file: every part's
// spline stored as SerializeSdcb stores it (`options` apply to each part),
// its name and its trim loops (exact doubles). kInvalidArgument (naming the
// part, "part 2: ...") as SerializeSdcb for a part's spline, or for no parts,
// a name that is not UTF-8 or longer than kMaxPartNameBytes, a trim loop of
// fewer than 3 rows, a row that is not a finite unit vector
// (|norm - 1| <= 1e-9), or consecutive rows equal or antipodal. `info`, if
// not null, receives the version, size and each part's storage.
StatusOr<std::string> SerializeSdcbModel(const Model& model,
                                         const SdcbWriteOptions& options = {},
                                         SdcbFileInfo* info = nullptr);

// Parses complete file contents of any version (1 to 3 read as one closed
// unnamed part whose source is the model's). Errors as ParseSdcb; version 4
// problems name the part ("part 2: ..."). `info`, if not null, receives
// what the file says about itself.
StatusOr<Model> ParseSdcbModel(std::string_view bytes,
                               SdcbFileInfo* info = nullptr);

// SerializeSdcbModel written to `path` atomically; messages start with
// `path`.
Status WriteSdcbModelFile(const Model& model, const std::string& path,
                          const SdcbWriteOptions& options = {},
                          SdcbFileInfo* info = nullptr);

// Reads and parses `path`: kIoError if it cannot be read, otherwise as
// ParseSdcbModel. Messages start with `path`.
StatusOr<Model> ReadSdcbModelFile(const std::string& path,
                                  SdcbFileInfo* info = nullptr);

// FNV-1a 64 (core/spline/spline_model.h) of the configurations' version 1
// BSIS bytes (docs/FORMAT.md): the hash version 2 stores in HEAD.
uint64_t HashConfigurations(const DelaunayConfigurations& configurations);

}  // namespace sdcb

#endif  // SDCB_IO_SDCB_SDCB_FILE_H_
