#pragma once
namespace tsubu {
inline constexpr const char* kVersion = "0.1.0";
}
