/// @file
/// @brief OutputFolder: a failed or interrupted run leaves no folder it created empty, and never removes a folder
/// that existed or holds a file.
#include "sdfccd/output_folder.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "../../plugin/core/src/temp_file_registry.h"
#include "sdfccd/error.h"
#include "sdfccd/output_file.h"

namespace sdfccd {
namespace {

namespace fs = std::filesystem;

class OutputFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = ::testing::TempDir() + "sdfccd-folder-XXXXXX";
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    m_dir = pattern;
  }
  void TearDown() override { fs::remove_all(m_dir); }
  std::string at(const std::string& name) const { return m_dir + "/" + name; }

  std::string m_dir;
};

TEST_F(OutputFolderTest, FoldersItCreatedAreRemovedWhenTheRunFails) {
  try {
    OutputFolder run(at("out/simulate/scene"));
    EXPECT_TRUE(fs::is_directory(at("out/simulate/scene")));
    throw std::runtime_error("the build failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_FALSE(fs::exists(at("out")));
  EXPECT_TRUE(fs::is_directory(m_dir));
  EXPECT_EQ(detail::liveTempFileCount(), 0);
}

TEST_F(OutputFolderTest, KeepAndFilesKeepTheFolder) {
  {
    OutputFolder run(at("kept/run"));
    run.keep();
  }
  EXPECT_TRUE(fs::is_directory(at("kept/run")));
  {
    OutputFolder run(at("partial/run"));
    writeOutputFile(at("partial/run/frames.csv"), "frame,time\n");
  }  // failed after writing a file: the file and its folders stay
  EXPECT_TRUE(fs::exists(at("partial/run/frames.csv")));
  EXPECT_EQ(detail::liveTempFileCount(), 0);
}

TEST_F(OutputFolderTest, AFolderThatExistedIsNeverRemoved) {
  fs::create_directories(at("existing"));
  { OutputFolder run(at("existing/")); }
  { OutputFolder run(at("existing")); }
  EXPECT_TRUE(fs::is_directory(at("existing")));
  { OutputFolder run(at("existing/new")); }
  EXPECT_TRUE(fs::is_directory(at("existing")));
  EXPECT_FALSE(fs::exists(at("existing/new")));
}

TEST_F(OutputFolderTest, AFileInTheWayIsAOneLineError) {
  std::ofstream(at("file")) << "x";
  for (const std::string& path : {at("file"), at("file/run")}) {
    try {
      OutputFolder run(path);
      ADD_FAILURE() << "accepted " << path;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos);
    }
  }
  // A failure part way undoes what was made: "fresh" is created, then the over-long name fails.
  EXPECT_THROW(OutputFolder run(at("fresh/" + std::string(300, 'n'))), Error);
  EXPECT_FALSE(fs::exists(at("fresh")));
}

TEST_F(OutputFolderTest, SigtermRemovesTheTemporaryFileAndTheEmptyFolders) {
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(ready[0]);
    installTempFileCleanupHandlers();
    OutputFolder run(at("out/run"));
    OutputFile frames(at("out/run/frames.csv"));
    for (int n = 0;; ++n) {
      frames.stream() << std::string(4096, 'f') << std::flush;
      if (n == 0 && ::write(ready[1], "r", 1) != 1) ::_exit(4);
      ::usleep(1000);
    }
  }
  ::close(ready[1]);
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  ::close(ready[0]);
  ::usleep(20000);
  ::kill(child, SIGTERM);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_FALSE(fs::exists(at("out")));
  EXPECT_TRUE(fs::is_empty(m_dir));
}

}  // namespace
}  // namespace sdfccd
