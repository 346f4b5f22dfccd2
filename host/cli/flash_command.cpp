// Checks the image before anything touches the board, then hands it to dfu-util or openocd (the
// tools that speak the ROM bootloader's DFU and the ST-LINK), started without a shell.
#include "host/cli/flash_command.h"
#include "host/cli/program_path.h"
#include "host/io/own_prefix.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <stdexcept>

extern char** environ;

namespace dg::host {

namespace {

constexpr uint32_t kFlashStart = 0x08000000, kFlashBytes = 512 * 1024;  // STM32F411CE (RM0383, section 3.3)
constexpr uint32_t kSramStart = 0x20000000, kSramBytes = 128 * 1024;

uint32_t word_at(const std::vector<uint8_t>& b, size_t at) {
  return static_cast<uint32_t>(b[at]) | static_cast<uint32_t>(b[at + 1]) << 8 | static_cast<uint32_t>(b[at + 2]) << 16 |
         static_cast<uint32_t>(b[at + 3]) << 24;
}

// Runs `argv` with our standard streams; its exit status, or -1 when it could not be started.
int run(std::vector<std::string> argv) {
  std::vector<char*> pointers;
  for (std::string& a : argv) pointers.push_back(a.data());
  pointers.push_back(nullptr);
  pid_t child = 0;
  if (posix_spawn(&child, argv[0].c_str(), nullptr, nullptr, pointers.data(), environ) != 0) return -1;
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string joined(const std::vector<std::string>& argv) {
  std::string out;
  for (const std::string& a : argv) out += (out.empty() ? "" : " ") + (a.find(' ') != std::string::npos ? "'" + a + "'" : a);
  return out;
}

}  // namespace

std::string stm32f411_image_problem(const std::vector<uint8_t>& bytes) {
  if (bytes.size() < 8) return "it is " + std::to_string(bytes.size()) + " bytes, shorter than a vector table";
  if (bytes.size() > kFlashBytes) return "it is " + std::to_string(bytes.size()) + " bytes, more than the 512 KB of flash";
  const uint32_t stack = word_at(bytes, 0), reset = word_at(bytes, 4);
  char why[160];
  if (stack <= kSramStart || stack > kSramStart + kSramBytes || stack % 4 != 0) {
    std::snprintf(why, sizeof why, "its first word 0x%08x is no initial stack pointer in SRAM (it is not an image for this chip)", stack);
    return why;
  }
  if ((reset & 1) == 0 || reset < kFlashStart || reset >= kFlashStart + bytes.size()) {
    std::snprintf(why, sizeof why, "its reset vector 0x%08x is not a Thumb address inside the image", reset);
    return why;
  }
  return "";
}

std::string packaged_image(const std::string& gauge) {
  std::vector<std::string> directories;
  if (const char* chosen = std::getenv("DIGITIZER_FIRMWARE_DIR"); chosen && *chosen) directories.push_back(chosen);
  if (const std::string prefix = own_prefix(); !prefix.empty()) directories.push_back(prefix + "/share/digitizer/firmware");
  for (const std::string& d : directories) {
    const std::string image = d + "/stm32f411-" + gauge + ".bin";
    if (access(image.c_str(), R_OK) == 0) return image;
  }
  return "";
}

void add_flash_command(CLI::App& app, FlashArgs& args) {
  CLI::App* flash = app.add_subcommand(
      "flash", "write the STM32F411 board's image (from the digitizer-firmware package) over USB DFU or an ST-LINK");
  flash->add_option("--gauge", args.gauge, "the gauge wired to the board: digimatic or caliper")
      ->capture_default_str()
      ->check(CLI::IsMember({"digimatic", "caliper"}));
  flash->add_option("--image", args.image, "write this .bin image instead of the packaged one")->check(CLI::ExistingFile);
  flash->add_flag("--stlink", args.stlink, "through an ST-LINK on the SWD pins (openocd) instead of the ROM bootloader's DFU (dfu-util)");
  flash->add_flag("--dry-run", args.dry_run, "check the image and print the command, but write nothing");
}

int run_flash_command(const CLI::App& app, const FlashArgs& args) {
  if (!app.got_subcommand("flash")) return -1;
  const std::string image = args.image.empty() ? packaged_image(args.gauge) : args.image;
  if (image.empty()) {
    throw std::runtime_error("no packaged image for a " + args.gauge + " gauge: install the digitizer-firmware package, set "
                             "DIGITIZER_FIRMWARE_DIR, give --image, or build one with scripts/flash");
  }
  std::ifstream in(image, std::ios::binary);
  const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (const std::string why = stm32f411_image_problem(bytes); !why.empty()) {
    throw std::runtime_error(image + ": not an STM32F411 image: " + why);
  }
  const char* tool = args.stlink ? "openocd" : "dfu-util";
  std::string program = find_on_path(tool);
  // 0483:df11 is the STM32 ROM bootloader in DFU mode; ":leave" starts the new image.
  std::vector<std::string> command =
      args.stlink ? std::vector<std::string>{tool, "-f", "interface/stlink.cfg", "-f", "target/stm32f4x.cfg", "-c",
                                             "program " + image + " 0x08000000 verify reset exit"}
                  : std::vector<std::string>{tool, "-d", "0483:df11", "-a", "0", "-s", "0x08000000:leave", "-D", image};
  std::printf("image %s (%zu bytes, checked: a vector table for the STM32F411)\n", image.c_str(), bytes.size());
  if (args.dry_run) {
    std::printf("would run: %s\n", joined(command).c_str());
    return 0;
  }
  if (program.empty()) {
    throw std::runtime_error(std::string(tool) + " is not installed: sudo apt install " + tool);
  }
  if (!args.stlink) {
    std::printf("the board must be in its ROM bootloader: hold BOOT0, tap NRST, release BOOT0\n");
  }
  command[0] = program;
  std::fflush(stdout);
  const int status = run(command);
  if (status != 0) {
    throw std::runtime_error(std::string(tool) + " failed (exit " + std::to_string(status) + "); " +
                             (args.stlink ? "check the ST-LINK's wiring (SWDIO, SWCLK, GND, 3V3)"
                                          : "is the board in its bootloader? `dfu-util -l` should list 0483:df11"));
  }
  std::printf("flashed; the board enumerates as 1209:0001 (`digitizer doctor` checks it)\n");
  return 0;
}

}  // namespace dg::host
