#pragma once
// Included first in every C++ file of this project (the top-level CMakeLists.txt passes
// -include), so that no file compiles its own copy of fmt's formatting engine.
//
// spdlog (Debian's, with the external fmt 9) formats every message with arguments through
// fmt::detail::vformat_to<char>. libfmt compiles that function once and exports it, but fmt 9's
// headers do not say so (fmt 10's do), so every file that logs with arguments instantiated it
// again: ~0.7 MB of code per file, a third of a small process's compile time under the
// sanitizers (lasonic-laser-driver's main: 17.6 s -> 11.9 s). The declaration below tells the
// compiler the instantiation exists elsewhere; the linker takes libfmt's. Other fmt versions
// (which declare it themselves, or differently) are left alone.
#if defined(__cplusplus) && __has_include(<fmt/format.h>)
#include <fmt/format.h>
#if FMT_VERSION >= 90000 && FMT_VERSION < 100000 && !defined(FMT_HEADER_ONLY)
FMT_BEGIN_NAMESPACE
namespace detail {
extern template FMT_API void vformat_to<char>(buffer<char>&, basic_string_view<char>,
                                              basic_format_args<FMT_BUFFER_CONTEXT(char)>, locale_ref);
}  // namespace detail
FMT_END_NAMESPACE
#endif
#endif
