// Test runner entry point. Leak checking is left to LeakSanitizer, whose reports
// are better than CppUTest's operator-new counting and do not fight ASan.
#include <CppUTest/CommandLineTestRunner.h>
#include <CppUTest/MemoryLeakWarningPlugin.h>

int main(int argc, char** argv) {
  MemoryLeakWarningPlugin::turnOffNewDeleteOverloads();
  return CommandLineTestRunner::RunAllTests(argc, argv);
}
