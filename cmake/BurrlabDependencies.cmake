# Third-party packages, all from Debian 12's archive (the Makefile installs them).
find_package(Boost 1.74 REQUIRED COMPONENTS random)  # Boost::random, Boost::headers
find_package(glm REQUIRED)                           # glm::glm
find_package(ZLIB REQUIRED)                          # ZLIB::ZLIB, gzip-encoded NRRD volumes
find_package(tomlplusplus 3 REQUIRED)                # tomlplusplus::tomlplusplus
find_package(nlohmann_json 3.11 REQUIRED)            # nlohmann_json::nlohmann_json
find_package(CLI11 REQUIRED)                         # CLI11::CLI11
find_package(fmt REQUIRED)                           # fmt::fmt
find_package(SQLite3 REQUIRED)                       # SQLite::SQLite3, the session journal
find_package(PkgConfig REQUIRED)
# SHA-256 of protocol files (the journal's identity check on --resume); none of
# the other listed libraries provides SHA-256.
pkg_check_modules(NETTLE REQUIRED IMPORTED_TARGET nettle)  # PkgConfig::NETTLE
# Plots (analysis/src/plot.cc) and the tests that read their PNGs back: PNG,
# PDF and SVG surfaces from one drawing routine, and real text layout.
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET cairo)  # PkgConfig::CAIRO
# The Novint Falcon's FTDI bridge over USB (runner/src/devices/libusb_transport).
pkg_check_modules(LIBUSB REQUIRED IMPORTED_TARGET libusb-1.0)  # PkgConfig::LIBUSB, <libusb.h>
# The subject window: GLFW 3.3 + OpenGL 3.3 core (no loader: GL_GLEXT_PROTOTYPES and
# GLFW_INCLUDE_GLCOREARB), Dear ImGui 1.86 (static, with its glfw and opengl3 backends),
# stb_image_write for screenshots (the implementation is inside libstb.so).
find_package(glfw3 3.3 REQUIRED)                     # glfw
find_package(OpenGL REQUIRED)                        # OpenGL::GL
pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)  # PkgConfig::IMGUI
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)      # PkgConfig::STB
# HID response boxes and gamepads (runner/src/devices/hid_response_box).
pkg_check_modules(HIDAPI REQUIRED IMPORTED_TARGET hidapi-hidraw)  # PkgConfig::HIDAPI
if(BURRLAB_BUILD_TESTS)
  # The hidapi backend's tests emulate a hidraw device in-process (run under
  # umockdev-wrapper).
  pkg_check_modules(UMOCKDEV REQUIRED IMPORTED_TARGET umockdev-1.0)  # PkgConfig::UMOCKDEV
  find_program(XVFB_RUN xvfb-run)
  find_program(UMOCKDEV_WRAPPER umockdev-wrapper)
  find_package(GTest REQUIRED)                       # GTest::gtest GTest::gtest_main
  find_package(benchmark REQUIRED)                   # benchmark::benchmark
endif()
