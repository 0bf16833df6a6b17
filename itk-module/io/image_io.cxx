// gdm::read_volume over ITK (see gdm/image_io.h). The only ITK translation unit
// of gdm_image_io. ITK's headers come first: ITK carries its own Eigen 3.3,
// which must be seen before the system Eigen 3.4 that the gdm headers include.
#include "itkGDCMImageIO.h"
#include "itkGDCMSeriesFileNames.h"
#include "itkImage.h"
#include "itkImageIOFactory.h"
#include "itkImageSeriesReader.h"
#include "itkMetaDataObject.h"
#include "itkMetaImageIO.h"
#include "itkNiftiImageIO.h"
#include "itkNrrdImageIO.h"
#include "itkVTKImageIO.h"
#include "itkSymmetricEigenAnalysis.h"  // ITK's Eigen before the system one

#include <gdcmScanner.h>
#include <gdcmTag.h>
#include <sys/stat.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <type_traits>

#include "gdm/image_io.h"

namespace gdm {
namespace {

using Image = itk::Image<float, 3>;

// ------------------------------------------------------------ helpers --

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && lower(s).compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r\n");
  return s.substr(a, b - a + 1);
}

std::string directory_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

std::string resolve(const std::string& header, const std::string& file) {
  if (!file.empty() && file[0] == '/') return file;
  return directory_of(header) + "/" + file;
}

// File size in bytes, or -1.
long long file_size(const std::string& path) {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) return -1;
  return static_cast<long long>(s.st_size);
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

std::string bytes_text(long double bytes) {
  std::ostringstream s;
  s.precision(3);
  if (bytes >= 1024.0L * 1024 * 1024)
    s << static_cast<double>(bytes / (1024.0L * 1024 * 1024)) << " GiB";
  else if (bytes >= 1024.0L * 1024)
    s << static_cast<double>(bytes / (1024.0L * 1024)) << " MiB";
  else
    s << static_cast<long long>(bytes) << " bytes";
  return s.str();
}

std::string dims_text(const std::vector<unsigned long long>& dims) {
  std::string s;
  for (std::size_t i = 0; i < dims.size(); ++i) s += (i ? " x " : "") + std::to_string(dims[i]);
  return s;
}

// A spacing read from a header: must be finite and positive.
void check_header_spacing(const std::string& path, const std::string& field, const std::vector<double>& values,
                          std::size_t axes, std::size_t first_axis = 0) {
  for (std::size_t d = 0; d < std::min(axes, values.size()); ++d)
    if (!(values[d] > 0.0) || !std::isfinite(values[d]))
      throw InvalidInput(path + ": the header's spacing (" + field + ") along axis " + std::to_string(first_axis + d) + " is " +
                         number(values[d]) + "; a spacing must be a positive finite number of mm");
}

std::vector<double> parse_numbers(const std::string& text) {
  std::vector<double> out;
  std::istringstream in(text);
  std::string word;
  while (in >> word) {
    const std::string w = lower(word);
    if (w == "nan" || w == "-nan" || w == "+nan")
      out.push_back(std::numeric_limits<double>::quiet_NaN());
    else if (w == "inf" || w == "+inf" || w == "infinity")
      out.push_back(std::numeric_limits<double>::infinity());
    else if (w == "-inf" || w == "-infinity")
      out.push_back(-std::numeric_limits<double>::infinity());
    else {
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      out.push_back(end && *end == '\0' ? v : std::numeric_limits<double>::quiet_NaN());
    }
  }
  return out;
}

std::string voxel_claim(const std::string& path, unsigned long long voxels, long double expected,
                        long double held, const std::string& where) {
  return path + ": the header claims " + std::to_string(voxels) + " voxels (" + bytes_text(expected) +
         " of data) but " + where + " holds " + bytes_text(held) + " (truncated or a header that lies)";
}

// ------------------------------------------------- per-format headers --
// ITK sanitises some header values (a spacing of 0 becomes 1, a negative one
// loses its sign) and trusts the header's voxel count; these read the header
// text / bytes themselves. Called twice: before ITK reads the header (the
// spacing only: `expected` < 0), and after (the data size against the voxel
// count ITK read).

// MetaImage (.mha/.mhd) header grammar, checked before MetaIO parses it.
// MetaIO trusts its header: a key of 300 bytes overflows its 255-byte name
// buffer (strcpy, abort), "NDims = 3000000e+00" reads three million numbers
// per array field (a hang), a short array line reads on into the next line.
// All three were found by fuzz_image_reader. So the header must be lines of
// "Key = value" (or "Key: value") in printable ASCII up to its
// ElementDataFile line, NDims an integer 1 to 8 before any array field,
// each array field exactly as many numbers as it needs, no field twice.
void check_metaimage_grammar(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const auto refuse = [&](int line, const std::string& why) {
    throw InvalidInput(path + " is not a well-formed MetaImage header: line " + std::to_string(line) + " " + why);
  };
  // Fields holding numbers: how many (0 = NDims of them, -1 = NDims squared).
  static const std::map<std::string, int> arrays{
      {"dimsize", 0},       {"elementspacing", 0},  {"elementsize", 0},   {"offset", 0},
      {"position", 0},      {"origin", 0},          {"centerofrotation", 0}, {"transformmatrix", -1},
      {"rotation", -1},     {"orientation", -1},    {"color", 4},         {"elementmin", 1},
      {"elementmax", 1},    {"headersize", 1},      {"compresseddatasize", 1}, {"id", 1},
      {"parentid", 1},      {"elementnumberofchannels", 1}};
  constexpr std::size_t kMaxKey = 128, kMaxValue = 400;
  std::map<std::string, int> seen;
  long long ndims = -1;
  std::string line;
  for (int at = 1; std::getline(in, line); ++at) {
    if (in.tellg() > (1 << 20) || line.size() > kMaxKey + kMaxValue + 8) refuse(at, "is too long for a header line");
    const auto sep = line.find_first_of("=:");
    if (sep == std::string::npos) {
      if (!trim(line).empty()) refuse(at, "is not 'Key = value'");
      continue;
    }
    const std::string key = trim(line.substr(0, sep));
    if (key.empty() || key.size() > kMaxKey) refuse(at, "has no key or a key longer than 128 characters");
    for (const char c : key)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.')
        refuse(at, "has a key with a byte that is not a letter, digit, '_', '-' or '.' (" +
                           std::to_string(static_cast<unsigned char>(c)) + ")");
    const std::string k = lower(key);
    const std::string value = line.substr(sep + 1);
    if (k == "elementdatafile") {
      const std::string name = value.substr(0, value.find('\0'));  // MetaIO's C string ends at a NUL
      if (trim(name).empty()) refuse(at, "names no data file");
      if (name.size() > kMaxValue) refuse(at, "names a data file longer than 400 characters");
      // MetaIO splits the name into words: bytes above 0x7e made it read
      // past the words it had allocated (found by fuzz_image_reader).
      for (const char c : name)
        if ((static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\r') || static_cast<unsigned char>(c) > 0x7e)
          refuse(at, "names a data file with a byte that is not printable ASCII (" +
                         std::to_string(static_cast<unsigned char>(c)) + "; rename the data file)");
      return;  // the data follow (LOCAL) or live elsewhere
    }
    if (value.size() > kMaxValue) refuse(at, "has a value longer than 400 characters");
    for (const char c : value)
      if ((static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\r') || static_cast<unsigned char>(c) > 0x7e)
        refuse(at, "holds a byte that is not printable ASCII (" + std::to_string(static_cast<unsigned char>(c)) + ")");
    if (seen[k]++ && (k == "ndims" || arrays.count(k))) refuse(at, "repeats the field " + key);
    if (k == "ndims") {
      const std::string v = trim(value);
      if (v.empty() || v.size() > 1 || v[0] < '1' || v[0] > '8') refuse(at, "gives NDims '" + v + "'; an integer 1 to 8 is needed");
      ndims = v[0] - '0';
      continue;
    }
    const auto a = arrays.find(k);
    if (a == arrays.end()) continue;
    if (a->second <= 0 && ndims < 0) refuse(at, "gives " + key + " before NDims");
    const long long needed = a->second == 0 ? ndims : a->second < 0 ? ndims * ndims : a->second;
    const std::vector<double> numbers = parse_numbers(value);
    if (static_cast<long long>(numbers.size()) != needed)
      refuse(at, "gives " + std::to_string(numbers.size()) + " numbers for " + key + "; " +
                         std::to_string(needed) + " are needed");
    if (k == "dimsize")
      for (const double d : numbers)
        if (!(d >= 1.0 && d <= 2147483647.0 && d == std::floor(d)))
          refuse(at, "gives a DimSize of " + number(d) + "; sizes are whole numbers from 1");
  }
  throw InvalidInput(path + " is not a well-formed MetaImage header: no ElementDataFile line ends it");
}

// A MetaImage data file pattern that snprintf may take as its format with
// one int argument: exactly one "%d" or "%i" (an optional 0 flag, a width of
// at most 3 digits), any number of "%%", no other '%'.
bool is_integer_name_pattern(const std::string& pattern) {
  int fields = 0;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (++i < pattern.size() && pattern[i] == '%') continue;
    if (i < pattern.size() && pattern[i] == '0') ++i;
    std::size_t digits = 0;
    while (i < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[i])) && digits < 4) ++i, ++digits;
    if (digits > 3 || i >= pattern.size() || (pattern[i] != 'd' && pattern[i] != 'i')) return false;
    ++fields;
  }
  return fields == 1;
}

// MetaImage (.mha/.mhd): spacing, and the data size of uncompressed data.
void check_metaimage(const std::string& path, unsigned long long voxels, long double expected) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::map<std::string, std::string> fields;
  std::streamoff header_end = -1;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto eq = line.find('=');
    const std::string key = eq == std::string::npos ? std::string() : lower(trim(line.substr(0, eq)));
    // A MetaImage header is text up to its ElementDataFile line: MetaIO reads
    // a header with control bytes in its own way, and one such file (corpus
    // itk_leak_mha_garbled_header2) reached a printf with a garbled format
    // inside MetaIO (found by the CI fuzz run).
    if (key != "elementdatafile")
      for (const char c : line)
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\r')
          throw InvalidInput(path + " is not a MetaImage header: its line " + std::to_string(number) +
                             " holds a control byte (" + std::to_string(static_cast<int>(c)) + ")");
    if (eq == std::string::npos) continue;
    // MetaIO keeps a value as a C string: it ends at a NUL byte (found by
    // fuzz_image_reader: "LColor\0%..." is the file LColor, not a pattern).
    const std::string value = line.substr(eq + 1);
    fields[key] = trim(value.substr(0, value.find('\0')));
    if (key == "elementdatafile") {
      header_end = in.tellg();
      break;
    }
    if (in.tellg() > 1 << 20) break;  // not a header
  }
  const std::size_t ndims = fields.count("ndims") ? static_cast<std::size_t>(std::atoi(fields["ndims"].c_str())) : 3;
  if (fields.count("elementspacing"))
    check_header_spacing(path, "ElementSpacing", parse_numbers(fields["elementspacing"]), ndims);
  else if (fields.count("elementsize"))
    check_header_spacing(path, "ElementSize", parse_numbers(fields["elementsize"]), ndims);
  if (expected < 0) return;
  const std::string data_field = fields["elementdatafile"];
  if (data_field.find('%') != std::string::npos && lower(data_field).rfind("list", 0) != 0) {
    // A file pattern "<printf pattern> [first [last [step]]]": MetaIO takes
    // the step from the words (3 words: (last - first) / slices, integer
    // division) and divides by it and loops by it: a step of 0 ended the
    // process with SIGFPE (found by fuzz_image_reader). Only integer words,
    // a step > 0 and first <= last are accepted.
    std::istringstream words(data_field);
    std::vector<std::string> w;
    for (std::string x; words >> x;) w.push_back(x);
    std::vector<long long> n;
    bool numbers = w.size() <= 4;
    for (std::size_t i = 1; i < w.size() && numbers; ++i) {
      char* end = nullptr;
      errno = 0;
      const long long v = std::strtoll(w[i].c_str(), &end, 10);
      numbers = errno == 0 && *end == '\0' && v > -(1LL << 30) && v < (1LL << 30);
      n.push_back(v);
    }
    const std::vector<double> dim_size = parse_numbers(fields["dimsize"]);
    const double last_dim = dim_size.empty() ? 0.0 : dim_size.back();  // NaN or 1e300 when the header lies
    const long long slices = last_dim >= 1.0 && last_dim < 1e9 ? static_cast<long long>(last_dim) : 0;
    long long step = 1;
    bool ordered = true;
    if (numbers && n.size() == 2) {
      ordered = n[0] <= n[1];
      step = slices > 0 ? (n[1] - n[0]) / slices : 0;
    } else if (numbers && n.size() == 3) {
      ordered = n[0] <= n[1];
      step = n[2];
    }
    if (!numbers || step <= 0 || !ordered)
      throw InvalidInput(path + ": its data file pattern '" + data_field +
                         "' is not '<pattern> <first> <last> <step>' with integers, first <= last and step > 0");
    // MetaIO hands the pattern to snprintf as its format with one int: a
    // format of the file's choosing ("%L", "%s", "%n") is undefined
    // behaviour (found by the CI fuzz run: "LOCJA%L" stopped AddressSanitizer
    // inside MetaIO). Only one integer field, "%d" or "%i" with an optional
    // 0 flag and a width of up to 3 digits, and "%%" are accepted.
    if (!is_integer_name_pattern(w.empty() ? std::string() : w[0]))
      throw InvalidInput(path + ": its data file pattern '" + data_field +
                         "' is not a file name with one integer field such as slice%03d.raw (%d or %i, an optional 0 "
                         "and width; %% for a percent sign)");
  }
  const std::string compressed = lower(fields["compresseddata"]);
  if (compressed == "true" || compressed == "1") return;  // sizes checked after reading (memory limit before)
  if (fields.count("headersize") && std::atoll(fields["headersize"].c_str()) < 0) return;  // data at the end
  const long long skip = fields.count("headersize") ? std::atoll(fields["headersize"].c_str()) : 0;
  const std::string data = fields["elementdatafile"];
  if (lower(data) == "local") {
    if (header_end < 0) return;
    const long long size = file_size(path);
    const long double held = static_cast<long double>(size - header_end);
    if (held < expected) throw InvalidInput(voxel_claim(path, voxels, expected, held, "the file"));
  } else if (!data.empty() && data.find('%') == std::string::npos && lower(data).rfind("list", 0) != 0) {
    // One data file (MetaIO reads a name without '%' and not LIST as one
    // file, spaces included). A missing one is refused here: ITK 5.2's
    // MetaIO leaks its stream when it cannot open it (found by fuzz_image_reader).
    const std::string raw = resolve(path, data);
    const long long size = file_size(raw);
    if (size < 0) throw InvalidInput(path + ": its data file " + raw + " does not exist");
    const long double held = static_cast<long double>(size - skip);
    if (held < expected) throw InvalidInput(voxel_claim(path, voxels, expected, held, "its data file " + raw));
  }
}

// NRRD (.nrrd/.nhdr): spacings / space directions, and raw data sizes.
void check_nrrd(const std::string& path, unsigned long long voxels, long double expected) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::map<std::string, std::string> fields;
  std::streamoff header_end = -1;
  bool first = true;
  while (std::getline(in, line)) {
    if (first) {
      first = false;
      if (line.rfind("NRRD", 0) != 0) return;
      continue;
    }
    if (trim(line).empty()) {
      header_end = in.tellg();
      break;
    }
    if (line[0] == '#') continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string key = lower(trim(line.substr(0, colon)));
    std::string value = line.substr(colon + 1);
    if (!value.empty() && value[0] == '=') continue;  // key:=value pairs
    fields[key] = trim(value);
    if (in.tellg() > 1 << 20) break;
  }
  if (header_end < 0) header_end = in.eof() ? file_size(path) : static_cast<std::streamoff>(in.tellg());
  const std::size_t ndims = fields.count("dimension") ? static_cast<std::size_t>(std::atoi(fields["dimension"].c_str())) : 3;
  if (fields.count("spacings")) {
    std::vector<double> s = parse_numbers(fields["spacings"]);
    check_header_spacing(path, "spacings", s, std::min<std::size_t>(ndims, 3));
  }
  if (fields.count("space directions")) {
    // "(a,b,c) (d,e,f) none ...": each vector's length is that axis' spacing.
    const std::string& text = fields["space directions"];
    std::size_t axis = 0, at = 0;
    while (at < text.size()) {
      while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
      if (at >= text.size()) break;
      if (text[at] == '(') {
        const auto close = text.find(')', at);
        if (close == std::string::npos) break;
        std::string inner = text.substr(at + 1, close - at - 1);
        std::replace(inner.begin(), inner.end(), ',', ' ');
        double norm2 = 0.0;
        for (double v : parse_numbers(inner)) norm2 += v * v;
        check_header_spacing(path, "length of its space direction", {std::sqrt(norm2)}, 1, axis);
        at = close + 1;
      } else {
        at = text.find(' ', at);  // "none"
        if (at == std::string::npos) break;
      }
      ++axis;
    }
  }
  if (expected < 0) return;
  const std::string encoding = lower(fields.count("encoding") ? fields["encoding"] : "raw");
  if (encoding != "raw") return;  // compressed or text: sizes checked by the reader / after reading
  long long skip = fields.count("byte skip") ? std::atoll(fields["byte skip"].c_str()) : 0;
  if (skip < 0) return;  // data at the end of the file
  if (fields.count("line skip") && std::atoll(fields["line skip"].c_str()) != 0) return;
  std::string data = fields.count("data file") ? fields["data file"] : fields["datafile"];
  if (data.empty()) {
    const long double held = static_cast<long double>(file_size(path) - header_end - skip);
    if (held < expected) throw InvalidInput(voxel_claim(path, voxels, expected, held, "the file"));
  } else if (data.find('%') == std::string::npos && data.find(' ') == std::string::npos && lower(data) != "list") {
    const std::string raw = resolve(path, data);
    const long long size = file_size(raw);
    if (size < 0) throw InvalidInput(path + ": its data file " + raw + " does not exist");
    const long double held = static_cast<long double>(size - skip);
    if (held < expected) throw InvalidInput(voxel_claim(path, voxels, expected, held, "its data file " + raw));
  }
}

template <typename T>
T get(const unsigned char* p, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

// NIfTI-1/-2 (.nii, .nii.gz; .hdr/.img pairs): pixdim, and the data size,
// for gzip data the size of what the stream really inflates to.

void check_nifti(const std::string& path, unsigned long long voxels, long double expected) {
  const bool pair = ends_with(path, ".hdr") || ends_with(path, ".hdr.gz");
  // Closed on every path, a throw included (check_header_spacing throws with
  // the stream open: an open file and zlib's buffers lost per bad header,
  // found by fuzz_image_reader).
  struct GzClose {
    void operator()(gzFile f) const { gzclose(f); }
  };
  std::unique_ptr<std::remove_pointer_t<gzFile>, GzClose> file(gzopen(path.c_str(), "rb"));
  gzFile f = file.get();
  if (!f) return;
  unsigned char h[540];
  const int got = gzread(f, h, sizeof h);
  if (got < 348) {
    file.reset();
    throw InvalidInput(path + ": the NIfTI header is truncated (" + std::to_string(std::max(got, 0)) +
                       " bytes; a NIfTI-1 header has 348)");
  }
  bool swap = false;
  int version = 0;
  if (get<std::int32_t>(h, false) == 348) version = 1;
  else if (get<std::int32_t>(h, true) == 348) version = 1, swap = true;
  else if (get<std::int32_t>(h, false) == 540) version = 2;
  else if (get<std::int32_t>(h, true) == 540) version = 2, swap = true;
  else {
    // Another sizeof_hdr: niftilib (inside ITK) still reads a NIfTI-1 /
    // Analyze header, its byte order told by dim[0] (1 to 7), so check it
    // the same way (found by fuzz_image_reader: sizeof_hdr 476 and a NaN sform).
    const auto plausible = [](std::int16_t d0) { return d0 >= 1 && d0 <= 7; };
    if (plausible(get<std::int16_t>(h + 40, false))) version = 1;
    else if (plausible(get<std::int16_t>(h + 40, true))) version = 1, swap = true;
  }
  if (version == 0 || (version == 2 && got < 540)) {
    file.reset();
    return;  // ITK accepted it: leave it to ITK
  }
  std::vector<double> pixdim(3);
  long double offset = 0;
  std::size_t ndim = 3;
  if (version == 1) {
    ndim = static_cast<std::size_t>(get<std::int16_t>(h + 40, swap));
    for (int d = 0; d < 3; ++d) pixdim[d] = get<float>(h + 80 + 4 * d, swap);
    offset = get<float>(h + 108, swap);
  } else {
    ndim = static_cast<std::size_t>(get<std::int64_t>(h + 16, swap));
    for (int d = 0; d < 3; ++d) pixdim[d] = get<double>(h + 112 + 8 * d, swap);
    offset = static_cast<long double>(get<std::int64_t>(h + 168, swap));
  }
  check_header_spacing(path, "pixdim", pixdim, std::min<std::size_t>(ndim, 3));
  // The orientation ITK takes (the sform when sform_code > 0, else the qform
  // when qform_code > 0) must be finite: ITK 5.2 runs an SVD on it, and vnl
  // aborts the process on a NaN or infinite entry (found by fuzz_image_reader).
  const int qform_code = version == 1 ? get<std::int16_t>(h + 252, swap) : get<std::int32_t>(h + 344, swap);
  const int sform_code = version == 1 ? get<std::int16_t>(h + 254, swap) : get<std::int32_t>(h + 348, swap);
  const auto field = [&](int i1, int i2) {  // float i of NIfTI-1 at byte i1, double of NIfTI-2 at i2
    return version == 1 ? static_cast<double>(get<float>(h + i1, swap)) : get<double>(h + i2, swap);
  };
  const auto check_finite = [&](const char* name, int i1, int i2, int count) {
    for (int i = 0; i < count; ++i) {
      const double v = field(i1 + 4 * i, i2 + 8 * i);
      // An origin of -1.7e38 mm, finite, also kept ITK's SVD iterating (fuzz_image_reader).
      if (!(std::abs(v) <= 1e9))
        throw InvalidInput(path + ": the NIfTI header's " + name + "[" + std::to_string(i) + "] is " + number(v) +
                           "; the orientation and origin must be finite and within 1e9 mm");
    }
  };
  // Finite is not enough: an sform of 1e22 and 1e-19 entries (and codes no
  // NIfTI writer uses) kept that SVD iterating (a hang, found by
  // fuzz_image_reader). So the codes must be NIfTI's (0 to 5), the sform's
  // axes between 1e-6 and 1e6 mm long and not degenerate, and the
  // quaternion's b, c, d at most 1.
  for (const auto& [name, code] : {std::pair<const char*, int>{"qform_code", qform_code}, {"sform_code", sform_code}})
    if (code < 0 || code > 5)
      throw InvalidInput(path + ": the NIfTI header's " + name + " is " + std::to_string(code) +
                         "; NIfTI's codes are 0 to 5");
  if (sform_code > 0) {
    check_finite("srow_x", 280, 400, 4);
    check_finite("srow_y", 296, 432, 4);
    check_finite("srow_z", 312, 464, 4);
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m(r, c) = field(280 + 16 * r + 4 * c, 400 + 32 * r + 8 * c);
    double product = 1.0;
    for (int c = 0; c < 3; ++c) {
      const double length = m.col(c).norm();
      if (!(length >= 1e-6 && length <= 1e6))
        throw InvalidInput(path + ": the NIfTI header's sform gives axis " + std::to_string(c) + " a voxel step of " +
                           number(length) + " mm; a usable orientation has steps between 1e-6 and 1e6 mm");
      product *= length;
    }
    if (!(std::abs(m.determinant()) >= 1e-6 * product))
      throw InvalidInput(path + ": the NIfTI header's sform is degenerate (its axes are parallel)");
  }
  if (qform_code > 0) {
    check_finite("quatern_b/c/d", 256, 352, 3);
    check_finite("qoffset_x/y/z", 268, 376, 3);
    for (int i = 0; i < 3; ++i)
      if (!(std::abs(field(256 + 4 * i, 352 + 8 * i)) <= 1.0 + 1e-4))
        throw InvalidInput(path + ": the NIfTI header's quatern_" + std::string(1, "bcd"[i]) + " is " +
                           number(field(256 + 4 * i, 352 + 8 * i)) + "; a rotation's quaternion has entries of at most 1");
  }
  if (expected < 0) {
    file.reset();
    return;
  }
  if (pair) {
    file.reset();
    std::string img = path.substr(0, path.size() - (ends_with(path, ".gz") ? 7 : 4)) + ".img";
    const long long size = file_size(img);
    if (size >= 0 && expected > size)
      throw InvalidInput(voxel_claim(path, voxels, expected, size, "its data file " + img));
    return;
  }
  if (!gzdirect(f)) {
    // Count what the gzip stream inflates to (a cut stream ends early with an error).
    long double total = got;
    std::vector<char> buffer(1 << 20);
    int n = 0;
    while ((n = gzread(f, buffer.data(), static_cast<unsigned>(buffer.size()))) > 0) total += n;
    int code = Z_OK;
    const char* message = gzerror(f, &code);
    const std::string error = n < 0 || (code != Z_OK && code != Z_STREAM_END) ? std::string(message ? message : "") : "";
    file.reset();
    if (total < offset + expected)
      throw InvalidInput(voxel_claim(path, voxels, expected, std::max<long double>(0, total - offset),
                                     "the gzip stream") + (error.empty() ? "" : " (zlib: " + error + ")"));
    if (!error.empty()) throw InvalidInput(path + ": the gzip stream is corrupt (zlib: " + error + ")");
    return;
  }
  file.reset();
  const long double held = static_cast<long double>(file_size(path)) - offset;
  if (held < expected) throw InvalidInput(voxel_claim(path, voxels, expected, std::max<long double>(0, held), "the file"));
}

// ------------------------------------------------------------- files --

std::string format_name(const itk::ImageIOBase* io) {
  const std::string n = io->GetNameOfClass();
  if (n == "MetaImageIO") return "MetaImage";
  if (n == "NrrdImageIO") return "NRRD";
  if (n == "NiftiImageIO") return "NIfTI";
  if (n == "VTKImageIO") return "VTK image";
  if (n == "GDCMImageIO") return "DICOM file";
  return n;
}

void check_memory(const std::string& what, const std::vector<unsigned long long>& dims, const ReadOptions& options) {
  long double voxels = 1;
  for (auto d : dims) voxels *= static_cast<long double>(d);
  const long double bytes = voxels * sizeof(float);
  if (options.memory_limit > 0 && bytes > static_cast<long double>(options.memory_limit))
    throw InvalidInput(what + " has " + dims_text(dims) + " voxels: " + bytes_text(bytes) +
                       " as float, more than the memory limit of " +
                       bytes_text(static_cast<long double>(options.memory_limit)) +
                       " (raise ReadOptions::memory_limit if this is really meant)");
}

// The header checks that must come before ITK reads the header (ITK may
// refuse a NaN or zero spacing with a parser message, or quietly repair it).
// They follow the same rule as image_io_for, the extension first: a .mha
// whose bytes began with "NRRD" used to get the NRRD checks and then went to
// MetaIO unchecked, which read past a data file name of bytes above 0x7e
// (found by fuzz_image_reader); such a file is now refused by its name.
void check_header_first(const std::string& path) {
  char magic[4] = {0, 0, 0, 0};
  std::ifstream(path, std::ios::binary).read(magic, 4);
  if (ends_with(path, ".mha") || ends_with(path, ".mhd")) {
    if (std::string(magic, 4) == "NRRD")
      throw InvalidInput("cannot read " + path +
                         ": not a readable image of the format its name gives: it is named as a MetaImage "
                         "(.mha/.mhd) but starts like a NRRD file (rename it .nrrd)");
    check_metaimage_grammar(path);
    check_metaimage(path, 0, -1);
  } else if (ends_with(path, ".nii") || ends_with(path, ".nii.gz") || ends_with(path, ".hdr") ||
             ends_with(path, ".hdr.gz")) {
    check_nifti(path, 0, -1);
  } else if (ends_with(path, ".nrrd") || ends_with(path, ".nhdr") || std::string(magic, 4) == "NRRD") {
    check_nrrd(path, 0, -1);
  }
}

// The reader of a file: the one its extension names (.mha/.mhd, .nrrd/.nhdr,
// .nii/.nii.gz/.hdr, .vtk), else the first of ITK's factories that can.
// Asking every factory let GDCM parse a .mha whose bytes looked like DICOM
// and allocate the 1.4 GB one element claimed (found by fuzz_image_reader).
// Null when the file cannot be read.
itk::ImageIOBase::Pointer image_io_for(const std::string& path) {
  itk::ImageIOBase::Pointer io;
  if (ends_with(path, ".mha") || ends_with(path, ".mhd")) io = itk::MetaImageIO::New();
  else if (ends_with(path, ".nrrd") || ends_with(path, ".nhdr")) io = itk::NrrdImageIO::New();
  else if (ends_with(path, ".nii") || ends_with(path, ".nii.gz") || ends_with(path, ".hdr") || ends_with(path, ".hdr.gz"))
    io = itk::NiftiImageIO::New();
  else if (ends_with(path, ".vtk")) io = itk::VTKImageIO::New();
  else return itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::IOFileModeEnum::ReadMode);
  return io->CanReadFile(path.c_str()) ? io : nullptr;
}

// The values of `count` pixels of component type T at `raw`, as float
// (static_cast, as ITK's ImageFileReader converts a scalar pixel).
template <typename T>
void convert_to_float(const char* raw, std::size_t count, float* out) {
  const T* in = reinterpret_cast<const T*>(raw);
  for (std::size_t i = 0; i < count; ++i) out[i] = static_cast<float>(in[i]);
}

// Reads the pixels of the IO's whole region (its header read) into `out`
// (io's voxel count): straight into it for a float file, else through one
// buffer of the file's type. Instead of ImageFileReader: its float image
// was copied into the volume's values afterwards, two float copies of the
// volume at once (a 512^3 volume of bytes peaked at 1.07 GB, issue 17's
// memory target is its float size plus 1 KB a face).
void read_pixels(const std::string& path, itk::ImageIOBase& io, std::vector<float>& out) {
  const unsigned int dims = io.GetNumberOfDimensions();
  itk::ImageIORegion region(dims);
  for (unsigned int d = 0; d < dims; ++d) {
    region.SetIndex(d, 0);
    region.SetSize(d, io.GetDimensions(d));
  }
  io.SetIORegion(region);
  using Component = itk::IOComponentEnum;
  const Component type = io.GetComponentType();
  if (type == Component::FLOAT) {
    io.Read(out.data());
    return;
  }
  const std::unique_ptr<char[]> raw(new char[out.size() * io.GetComponentSize()]);
  io.Read(raw.get());
  switch (type) {
    case Component::UCHAR: return convert_to_float<unsigned char>(raw.get(), out.size(), out.data());
    case Component::CHAR: return convert_to_float<signed char>(raw.get(), out.size(), out.data());
    case Component::USHORT: return convert_to_float<unsigned short>(raw.get(), out.size(), out.data());
    case Component::SHORT: return convert_to_float<short>(raw.get(), out.size(), out.data());
    case Component::UINT: return convert_to_float<unsigned int>(raw.get(), out.size(), out.data());
    case Component::INT: return convert_to_float<int>(raw.get(), out.size(), out.data());
    case Component::ULONG: return convert_to_float<unsigned long>(raw.get(), out.size(), out.data());
    case Component::LONG: return convert_to_float<long>(raw.get(), out.size(), out.data());
    case Component::ULONGLONG: return convert_to_float<unsigned long long>(raw.get(), out.size(), out.data());
    case Component::LONGLONG: return convert_to_float<long long>(raw.get(), out.size(), out.data());
    case Component::DOUBLE: return convert_to_float<double>(raw.get(), out.size(), out.data());
    default:
      throw InvalidInput("cannot read " + path + ": its pixels are of type " +
                         itk::ImageIOBase::GetComponentTypeAsString(type) + ", not numbers gdm reads");
  }
}

// The file's pixels as float, its geometry into `info` (dims, spacing,
// origin, direction as ImageFileReader gives them to a 3D image: the IO's
// first three axes, with its default directions when it has more).
std::vector<float> read_file(const std::string& path, const ReadOptions& options, ImageInfo& info) {
  check_header_first(path);
  itk::ImageIOBase::Pointer io = image_io_for(path);
  if (!io)
    throw InvalidInput("cannot read " + path +
                       ": not a readable image of the format its name gives (supported: DICOM, .mha/.mhd, "
                       ".nrrd/.nhdr, .nii/.nii.gz, .vtk; is the header corrupt?)");
  io->SetFileName(path);
  try {
    io->ReadImageInformation();
  } catch (const itk::ExceptionObject& e) {
    throw InvalidInput("cannot read the header of " + path + " (corrupt or unsupported): " + e.GetDescription());
  }
  info.format = format_name(io);
  info.pixel_type = itk::ImageIOBase::GetComponentTypeAsString(io->GetComponentType());
  const unsigned int dims = io->GetNumberOfDimensions();
  if (io->GetNumberOfComponents() != 1)
    throw InvalidInput(path + " has " + std::to_string(io->GetNumberOfComponents()) +
                       " components per pixel; gdm needs a scalar image");
  if (dims < 3 || (dims == 3 && (io->GetDimensions(2) < 2)))
    throw InvalidInput(path + " is a 2D image; gdm needs a 3D volume" +
                       (info.format == "DICOM file" ? std::string(" (pass the folder of the DICOM series)") : ""));
  for (unsigned int d = 3; d < dims; ++d)
    if (io->GetDimensions(d) > 1)
      throw InvalidInput(path + " is a " + std::to_string(dims) + "D image; gdm needs a 3D volume");

  std::vector<unsigned long long> size;
  unsigned long long voxels = 1;
  for (unsigned int d = 0; d < dims; ++d) {
    size.push_back(io->GetDimensions(d));
    voxels *= io->GetDimensions(d);
  }
  const long double expected = static_cast<long double>(voxels) * io->GetComponentSize();
  if (info.format == "MetaImage") check_metaimage(path, voxels, expected);
  if (info.format == "NRRD") check_nrrd(path, voxels, expected);
  if (info.format == "NIfTI") check_nifti(path, voxels, expected);
  if (const auto* vtk = dynamic_cast<const itk::VTKImageIO*>(io.GetPointer())) {
    // Legacy VTK: the data follows the header; ASCII needs at least 2 bytes a value.
    const bool ascii = vtk->GetFileType() == itk::IOFileEnum::ASCII;
    const long double needed = ascii ? 2.0L * static_cast<long double>(voxels) - 1 : expected;
    const long double held =
        static_cast<long double>(file_size(path)) - static_cast<long double>(vtk->GetHeaderSize());
    if (held < needed)
      throw InvalidInput(voxel_claim(path, voxels, needed, std::max<long double>(0, held), "the file"));
  }
  for (unsigned int d = 0; d < 3; ++d)
    check_header_spacing(path, "as read by ITK", {io->GetSpacing(d)}, 1);
  size.resize(3);
  check_memory(path, size, options);

  for (unsigned int d = 0; d < 3; ++d) {
    info.dims[d] = io->GetDimensions(d);
    info.spacing[d] = io->GetSpacing(d);
    info.origin[d] = io->GetOrigin(d);
    const std::vector<double> axis = dims > 3 ? io->GetDefaultDirection(d) : io->GetDirection(d);
    for (unsigned int c = 0; c < 3; ++c) info.direction[3 * c + d] = axis[c];  // column d: axis d
  }
  std::vector<float> values(static_cast<std::size_t>(voxels));
  try {
    read_pixels(path, *io, values);
  } catch (const itk::ExceptionObject& e) {
    throw InvalidInput("cannot read " + path + ": " + e.GetDescription());
  }
  return values;
}

// ------------------------------------------------------ DICOM series --

bool parse_vector(const std::string& value, std::size_t n, double* out) {
  std::string v = value;
  for (char& c : v)
    if (c == '\\') c = ' ';
  const std::vector<double> numbers = parse_numbers(v);
  if (numbers.size() != n) return false;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(numbers[i])) return false;
    out[i] = numbers[i];
  }
  return true;
}

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string point_text(const double p[3]) {
  return "(" + number(p[0]) + ", " + number(p[1]) + ", " + number(p[2]) + ")";
}

struct SeriesGeometry {
  bool positions = false;   // every slice has 0020|0032 and 0020|0037
  double step = 0.0;        // median step along the normal, > 0
  double normal[3] = {0, 0, 1};
  double sign = 1.0;        // +1 when the file order runs along +normal
};

// The slice geometry of `files` (in the order ITK will stack them), checked.
SeriesGeometry check_series_geometry(const std::string& folder, const std::string& uid,
                                     const std::vector<std::string>& files, ImageInfo& info) {
  const std::string series = "the DICOM series " + uid + " in " + folder;
  const gdcm::Tag position_tag(0x0020, 0x0032), orientation_tag(0x0020, 0x0037), sop_tag(0x0008, 0x0018);
  gdcm::Scanner scanner;
  scanner.AddTag(position_tag);
  scanner.AddTag(orientation_tag);
  scanner.AddTag(sop_tag);
  if (!scanner.Scan(files)) throw InvalidInput("cannot scan the headers of " + series);
  auto value = [&](const std::string& file, const gdcm::Tag& tag) -> std::string {
    const char* v = scanner.GetValue(file.c_str(), tag);
    return v ? trim(v) : std::string();
  };

  // The same slice twice (a copied file).
  std::map<std::string, std::string> seen;
  for (const auto& f : files) {
    const std::string sop = value(f, sop_tag);
    if (sop.empty()) continue;
    auto [at, fresh] = seen.emplace(sop, f);
    if (!fresh)
      throw InvalidInput(series + " holds the same slice twice: " + base_name(at->second) + " and " + base_name(f) +
                         " have the same SOP instance UID " + sop + " (a duplicated file)");
  }

  SeriesGeometry g;
  const std::size_t n = files.size();
  std::vector<std::array<double, 3>> p(n);
  double row_col[6] = {0, 0, 0, 0, 0, 0};
  for (std::size_t k = 0; k < n; ++k) {
    double o[6];
    if (!parse_vector(value(files[k], position_tag), 3, p[k].data()) ||
        !parse_vector(value(files[k], orientation_tag), 6, o)) {
      info.warnings.push_back(series + " has no per-slice positions (0020|0032) and orientations (0020|0037); "
                              "the slice spacing may be wrong");
      return g;
    }
    if (k == 0) {
      std::copy(o, o + 6, row_col);
    } else {
      for (int i = 0; i < 6; ++i)
        if (std::abs(o[i] - row_col[i]) > 1e-4)
          throw InvalidInput(series + " mixes slice orientations (0020|0037): " + base_name(files[0]) + " and " +
                             base_name(files[k]) + " differ; gdm needs parallel slices");
    }
  }
  g.positions = true;
  const double* r = row_col;
  const double* c = row_col + 3;
  double nrm[3] = {r[1] * c[2] - r[2] * c[1], r[2] * c[0] - r[0] * c[2], r[0] * c[1] - r[1] * c[0]};
  const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
  if (!(len > 0.5))
    throw InvalidInput(series + " has a degenerate slice orientation (0020|0037) in " + base_name(files[0]));
  for (double& v : nrm) v /= len;
  std::copy(nrm, nrm + 3, g.normal);

  // Distances along the normal; ITK stacks the files in this order.
  std::vector<double> along(n);
  for (std::size_t k = 0; k < n; ++k)
    along[k] = (p[k][0] - p[0][0]) * nrm[0] + (p[k][1] - p[0][1]) * nrm[1] + (p[k][2] - p[0][2]) * nrm[2];
  g.sign = along[n - 1] >= 0.0 ? 1.0 : -1.0;
  std::vector<double> steps(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k) steps[k] = g.sign * (along[k + 1] - along[k]);
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  const double tiny = std::max(1e-4, 1e-3 * std::abs(median));
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (std::abs(steps[k]) <= tiny)
      throw InvalidInput(series + " has two slices at the same position " + point_text(p[k + 1].data()) + ": " +
                         base_name(files[k]) + " and " + base_name(files[k + 1]) + " (a duplicated slice)");
    if (steps[k] < 0.0)
      throw InvalidInput(series + " is not ordered along the slice normal at " + base_name(files[k + 1]));
  }
  if (!(median > 0.0)) throw InvalidInput(series + " has no slice spacing (every slice at the same position)");
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (steps[k] > 1.5 * median)
      throw InvalidInput(series + " has missing slices: a gap of " + number(steps[k]) + " mm between " +
                         base_name(files[k]) + " and " + base_name(files[k + 1]) + ", " +
                         number(steps[k] / median) + " times the median slice step of " + number(median) + " mm");
  }
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (std::abs(steps[k] - median) > 0.01 * median)
      throw InvalidInput(series + " has non-uniform slice spacing: the step between " + base_name(files[k]) +
                         " and " + base_name(files[k + 1]) + " is " + number(steps[k]) +
                         " mm, the median step " + number(median) + " mm (more than 1% apart)");
  }
  g.step = median;

  // Gantry tilt: the slice positions leave the line along the normal.
  double lateral = 0.0;
  for (std::size_t k = 1; k < n; ++k) {
    double off2 = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double o = p[k][i] - p[0][i] - along[k] * nrm[i];
      off2 += o * o;
    }
    lateral = std::max(lateral, std::sqrt(off2));
  }
  const double extent = std::abs(along[n - 1]);
  const double tilt = std::atan2(lateral, extent) * 180.0 / 3.14159265358979323846;
  if (lateral > 1e-3) {
    std::ostringstream s;
    s << series << " has a gantry tilt of " << number(tilt) << " degrees (the slice positions leave the slice normal "
      << "by up to " << number(lateral) << " mm)";
    // Refused when the stacked grid would be sheared by more than a tenth of a
    // degree: the volume would be distorted.
    if (tilt > 0.1)
      throw InvalidInput(s.str() + "; gdm needs slices stacked along their normal (resample the series first)");
    info.warnings.push_back(s.str() + "; ignored");
  }
  return g;
}

Image::Pointer read_dicom_series(const std::string& folder, const ReadOptions& options, ImageInfo& info) {
  auto names = itk::GDCMSeriesFileNames::New();
  names->SetUseSeriesDetails(true);
  // A folder without DICOM is reported below; ITK's own warning would only repeat it.
  const bool warnings = itk::Object::GetGlobalWarningDisplay();
  itk::Object::SetGlobalWarningDisplay(false);
  names->SetDirectory(folder);
  const std::vector<std::string> uids = names->GetSeriesUIDs();
  itk::Object::SetGlobalWarningDisplay(warnings);
  if (uids.empty()) throw InvalidInput("no DICOM series in the folder " + folder);
  info.series_count = uids.size();

  std::string chosen;
  const std::string& wanted = options.series_uid;
  if (!wanted.empty()) {
    for (const auto& uid : uids)
      if (uid == wanted || uid.rfind(wanted + ".", 0) == 0 || uid.rfind(wanted, 0) == 0) chosen = uid;
    if (chosen.empty()) {
      std::string list;
      for (const auto& uid : uids) list += "\n  " + uid;
      throw InvalidOption("no such series " + wanted + " in " + folder + "; it holds:" + list);
    }
  } else {
    std::size_t most = 0;
    for (const auto& uid : uids) {
      const std::size_t n = names->GetFileNames(uid).size();
      if (n > most) {
        most = n;
        chosen = uid;
      }
    }
  }
  const std::vector<std::string> files = names->GetFileNames(chosen);
  info.series_uid = chosen;
  info.slices = files.size();
  info.format = "DICOM series";
  if (files.size() < 2)
    throw InvalidInput("the DICOM series " + chosen + " in " + folder + " has " + std::to_string(files.size()) +
                       " slice; gdm needs a 3D volume");

  const SeriesGeometry geometry = check_series_geometry(folder, chosen, files, info);

  auto io = itk::GDCMImageIO::New();
  io->SetFileName(files.front());
  try {
    io->ReadImageInformation();
  } catch (const itk::ExceptionObject& e) {
    throw InvalidInput("cannot read the DICOM file " + files.front() + ": " + e.GetDescription());
  }
  check_memory("the DICOM series " + chosen + " in " + folder,
               {io->GetDimensions(0), io->GetNumberOfDimensions() > 1 ? io->GetDimensions(1) : 1, files.size()},
               options);

  auto reader = itk::ImageSeriesReader<Image>::New();
  reader->SetImageIO(io);
  reader->SetFileNames(files);
  try {
    reader->Update();
  } catch (const itk::ExceptionObject& e) {
    throw InvalidInput("cannot read the DICOM series " + chosen + " in " + folder + ": " + e.GetDescription());
  }
  info.pixel_type = itk::ImageIOBase::GetComponentTypeAsString(io->GetInternalComponentType());
  Image::Pointer image = reader->GetOutput();
  image->DisconnectPipeline();
  if (geometry.positions) {
    // The slice spacing from the positions (not SliceThickness), the third
    // axis along the normal in file order.
    auto spacing = image->GetSpacing();
    spacing[2] = geometry.step;
    image->SetSpacing(spacing);
    auto direction = image->GetDirection();
    for (int i = 0; i < 3; ++i) direction[i][2] = geometry.sign * geometry.normal[i];
    image->SetDirection(direction);
  } else {
    info.warnings.back() += " (" + number(image->GetSpacing()[2]) + " mm)";
  }
  return image;
}

}  // namespace

// A DICOM series' image's pixels as float, its geometry into `info`.
std::vector<float> take_pixels(Image::Pointer image, ImageInfo& info) {
  const auto region = image->GetBufferedRegion();
  for (unsigned int d = 0; d < 3; ++d) {
    info.dims[d] = region.GetSize()[d];
    info.spacing[d] = image->GetSpacing()[d];
    info.origin[d] = image->GetOrigin()[d];
    for (unsigned int c = 0; c < 3; ++c) info.direction[3 * d + c] = image->GetDirection()[d][c];
  }
  const float* values = image->GetBufferPointer();
  return std::vector<float>(values, values + region.GetNumberOfPixels());
}

Volume read_volume(const std::string& path, const ReadOptions& options, ImageInfo* out) {
  ImageInfo local;
  ImageInfo& info = out ? *out : local;
  info = ImageInfo{};
  info.path = path;
  if (path.empty()) throw InvalidInput("no input file given");
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) throw InvalidInput("no such file or folder: " + path);
  std::vector<float> data;
  if (S_ISDIR(s.st_mode)) {
    data = take_pixels(read_dicom_series(path, options, info), info);  // ITK's image freed on return
  } else if (!S_ISREG(s.st_mode)) {
    const char* kind = S_ISFIFO(s.st_mode) ? "a FIFO (named pipe)"
                       : S_ISCHR(s.st_mode) ? "a character device"
                       : S_ISBLK(s.st_mode) ? "a block device"
                       : S_ISSOCK(s.st_mode) ? "a socket"
                                             : "not a regular file";
    throw InvalidInput(path + " is " + std::string(kind) + ", not a regular file; gdm reads volume files and "
                       "DICOM folders");
  } else {
    data = read_file(path, options, info);
  }

  for (unsigned int d = 0; d < 3; ++d) {
    if (info.dims[d] < 2)
      throw InvalidInput(path + " has only " + std::to_string(info.dims[d]) + " voxel along axis " +
                         std::to_string(d) + "; gdm needs a 3D volume");
    if (!(info.spacing[d] > 0.0) || !std::isfinite(info.spacing[d]))
      throw InvalidInput(path + " has an invalid spacing along axis " + std::to_string(d) + " (" +
                         number(info.spacing[d]) + ")");
  }
  const ValueRange range = value_range(data.data(), data.size());
  if (range.non_finite > 0)
    throw InvalidInput(path + " holds " + std::to_string(range.non_finite) + " non-finite voxels (" +
                       std::to_string(range.nan) + " NaN, " + std::to_string(range.non_finite - range.nan) +
                       " infinite) of " + std::to_string(data.size()) + "; gdm needs finite values");
  info.minimum = range.min;
  info.maximum = range.max;
  if (range.min == range.max)
    throw InvalidVolume(path + " is constant (every voxel is " + std::to_string(range.min) + "): nothing to segment");

  Vec3 spacing, origin;
  Eigen::Matrix3d direction;
  for (int i = 0; i < 3; ++i) {
    spacing[i] = info.spacing[i];
    origin[i] = info.origin[i];
    for (int j = 0; j < 3; ++j) direction(i, j) = info.direction[3 * i + j];
  }
  return Volume({static_cast<int>(info.dims[0]), static_cast<int>(info.dims[1]), static_cast<int>(info.dims[2])},
                std::move(data), spacing, origin, direction);
}

}  // namespace gdm
