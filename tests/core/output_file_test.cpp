/// @file
/// @brief OutputFile and checkOutput: each case of the policy by name — planted links never followed, user-named links
/// followed, modes kept, devices and FIFOs written in place, an input never overwritten, and no temporary file left by
/// an error, an exception or SIGTERM/SIGINT.
#include "sdfccd/output_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "../../plugin/core/src/temp_file_registry.h"
#include "sdfccd/error.h"

namespace sdfccd {
namespace {

namespace fs = std::filesystem;

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

mode_t modeOf(const std::string& path) {
  struct stat info {};
  EXPECT_EQ(::stat(path.c_str(), &info), 0) << path;
  return info.st_mode;
}

/// Every entry of a folder: a link by its destination, a regular file by its mode and contents, anything else
/// by its type (opening a FIFO would wait for a writer).
std::map<std::string, std::string> snapshot(const std::string& folder) {
  std::map<std::string, std::string> entries;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string path = entry.path().string();
    if (entry.is_symlink()) {
      entries[entry.path().filename()] = "link -> " + fs::read_symlink(entry.path()).string();
    } else if (!entry.is_regular_file()) {
      entries[entry.path().filename()] = "type " + std::to_string(modeOf(path) & S_IFMT);
    } else {
      entries[entry.path().filename()] = std::to_string(modeOf(path) & 07777) + ":" + readText(path);
    }
  }
  return entries;
}

/// A fresh folder per test, removed afterwards.
class OutputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = ::testing::TempDir() + "sdfccd-output-XXXXXX";
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    m_dir = pattern;
    m_savedUmask = ::umask(022);
  }
  void TearDown() override {
    ::umask(m_savedUmask);
    fs::remove_all(m_dir);
  }
  std::string at(const std::string& name) const { return m_dir + "/" + name; }

  std::string m_dir;
  mode_t m_savedUmask = 022;
};

TEST_F(OutputFileTest, NewFileGetsTheUmaskModeAndTheContents) {
  writeOutputFile(at("new.txt"), "hello\n");
  EXPECT_EQ(readText(at("new.txt")), "hello\n");
  EXPECT_EQ(modeOf(at("new.txt")) & 07777, 0644u);
  ::umask(077);
  writeOutputFile(at("private.txt"), "x");
  EXPECT_EQ(modeOf(at("private.txt")) & 07777, 0600u);
  EXPECT_EQ(snapshot(m_dir).size(), 2u);  // no temporary file left
  EXPECT_EQ(detail::liveTempFileCount(), 0);
}

TEST_F(OutputFileTest, ExistingTargetKeepsMode0600) {
  writeText(at("secret.txt"), "old");
  ASSERT_EQ(::chmod(at("secret.txt").c_str(), 0600), 0);
  writeOutputFile(at("secret.txt"), "new");
  EXPECT_EQ(readText(at("secret.txt")), "new");
  EXPECT_EQ(modeOf(at("secret.txt")) & 07777, 0600u);
  writeText(at("tool.sh"), "old");
  ASSERT_EQ(::chmod(at("tool.sh").c_str(), 0751), 0);
  writeOutputFile(at("tool.sh"), "new");
  EXPECT_EQ(modeOf(at("tool.sh")) & 07777, 0751u);
}

TEST_F(OutputFileTest, TemporaryFileIsPrivateWhileWriting) {
  OutputFile file(at("out.csv"));
  file.stream() << "partial";
  EXPECT_TRUE(file.replacesTarget());
  int temporaries = 0;
  for (const auto& entry : fs::directory_iterator(m_dir)) {
    const std::string name = entry.path().filename();
    ASSERT_EQ(name.rfind("out.csv.tmp-", 0), 0u) << name;
    EXPECT_EQ(name.size(), std::string("out.csv.tmp-").size() + 12);  // the random part
    EXPECT_EQ(modeOf(entry.path()) & 07777, 0600u);
    ++temporaries;
  }
  EXPECT_EQ(temporaries, 1);
  EXPECT_FALSE(fs::exists(at("out.csv")));  // nothing at the target before commit()
  EXPECT_EQ(detail::liveTempFileCount(), 1);
  file.commit();
  EXPECT_EQ(readText(at("out.csv")), "partial");
  EXPECT_EQ(detail::liveTempFileCount(), 0);
}

TEST_F(OutputFileTest, PlantedSymlinksInTheFolderAreNeverFollowed) {
  // Temporary names are random: plant links at the predictable names (<target>.tmp-<pid>-<n>) and at guesses of
  // the random ones, and check that nothing but the target changes, in the folder and at the links' destination.
  const std::string victimFolder = at("victims");
  fs::create_directory(victimFolder);
  writeText(victimFolder + "/victim.txt", "precious");
  const std::string folder = at("work");
  fs::create_directory(folder);
  for (const std::string& name :
       {"o.sdf.tmp-" + std::to_string(::getpid()) + "-0", "o.sdf.tmp-" + std::to_string(::getpid()) + "-1",
        std::string("o.sdf.tmp-"), std::string("o.sdf.tmp-000000000000"), std::string(".o.sdf.tmp"),
        std::string("o.sdf.tmp")}) {
    fs::create_symlink(victimFolder + "/victim.txt", folder + "/" + name);
  }
  fs::create_symlink(victimFolder + "/missing.txt", folder + "/o.sdf.tmp-dangling");
  auto before = snapshot(folder);
  const auto victimsBefore = snapshot(victimFolder);
  for (int n = 0; n < 20; ++n) writeOutputFile(folder + "/o.sdf", "field " + std::to_string(n));
  checkOutput(folder + "/o.sdf");
  EXPECT_EQ(snapshot(victimFolder), victimsBefore);
  auto after = snapshot(folder);
  ASSERT_EQ(after.count("o.sdf"), 1u);
  EXPECT_EQ(after["o.sdf"], "420:field 19");
  after.erase("o.sdf");
  EXPECT_EQ(after, before);
}

TEST_F(OutputFileTest, UserNamedSymlinkIsFollowedLikeCp) {
  fs::create_directory(at("real"));
  writeText(at("real/target.txt"), "old");
  ASSERT_EQ(::chmod(at("real/target.txt").c_str(), 0640), 0);
  fs::create_symlink("real/target.txt", at("relative-link"));  // relative to the link's own folder
  fs::create_symlink(at("relative-link"), at("link-to-link"));
  writeOutputFile(at("link-to-link"), "new");
  EXPECT_TRUE(fs::is_symlink(at("link-to-link")));
  EXPECT_TRUE(fs::is_symlink(at("relative-link")));
  EXPECT_EQ(readText(at("real/target.txt")), "new");
  EXPECT_EQ(modeOf(at("real/target.txt")) & 07777, 0640u);
  EXPECT_EQ(snapshot(at("real")).size(), 1u);  // the temporary file was beside the target, and is gone
  // A dangling link creates the file it points to.
  fs::create_symlink("real/created.txt", at("dangling"));
  OutputFile file(at("dangling"));
  EXPECT_EQ(file.targetPath(), m_dir + "/real/created.txt");
  file.stream() << "made";
  file.commit();
  EXPECT_EQ(readText(at("real/created.txt")), "made");
  EXPECT_TRUE(fs::is_symlink(at("dangling")));
}

TEST_F(OutputFileTest, DevNullStaysACharacterDevice) {
  OutputFile file("/dev/null");
  EXPECT_FALSE(file.replacesTarget());
  file.stream() << std::string(100000, 'x');
  file.commit();
  EXPECT_TRUE(S_ISCHR(modeOf("/dev/null")));
  writeOutputFile("/dev/null", "again");
  EXPECT_TRUE(S_ISCHR(modeOf("/dev/null")));
  checkOutput("/dev/null", {at("whatever")});
  // A link to /dev/null is followed to the device too.
  fs::create_symlink("/dev/null", at("null-link"));
  writeOutputFile(at("null-link"), "through the link");
  EXPECT_TRUE(fs::is_symlink(at("null-link")));
  EXPECT_TRUE(S_ISCHR(modeOf("/dev/null")));
}

TEST_F(OutputFileTest, FifoIsWrittenDirectly) {
  ASSERT_EQ(::mkfifo(at("pipe").c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = readText(at("pipe")); });
  const std::string payload(300000, 'p');  // more than a pipe buffer: the writer must wait for the reader
  {
    OutputFile file(at("pipe"));
    EXPECT_FALSE(file.replacesTarget());
    file.stream() << payload << "end";
    file.commit();
  }
  reader.join();
  EXPECT_EQ(received, payload + "end");
  EXPECT_TRUE(S_ISFIFO(modeOf(at("pipe"))));
  EXPECT_EQ(snapshot(m_dir).size(), 1u);
  checkOutput(at("pipe"));  // checked without opening (no reader now: opening would block)
}

TEST_F(OutputFileTest, DashIsStandardOutput) {
  const std::string captured = at("stdout.txt");
  std::fflush(stdout);
  const int saved = ::dup(STDOUT_FILENO);
  const int capture = ::open(captured.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  ASSERT_GE(capture, 0);
  ::dup2(capture, STDOUT_FILENO);
  ::close(capture);
  {
    OutputFile file("-");
    EXPECT_FALSE(file.replacesTarget());
    file.stream() << "to stdout";
    file.commit();
  }
  EXPECT_THROW(checkOutput("-", {captured}), Error);  // `sdfccd ... -o - > input` is refused too
  ::dup2(saved, STDOUT_FILENO);
  ::close(saved);
  EXPECT_NE(::fcntl(STDOUT_FILENO, F_GETFD), -1);  // standard output was not closed
  EXPECT_EQ(readText(captured), "to stdout");
}

TEST_F(OutputFileTest, OutputThatIsAnInputIsRefused) {
  writeText(at("m.obj"), "v 0 0 0\n");
  writeText(at("other.obj"), "v 1 1 1\n");
  fs::create_symlink("m.obj", at("link.obj"));
  ASSERT_EQ(::link(at("m.obj").c_str(), at("hard.obj").c_str()), 0);
  for (const std::string& output : {at("m.obj"), at("link.obj"), at("hard.obj"), at("./m.obj")}) {
    try {
      checkOutput(output, {at("other.obj"), at("m.obj")});
      ADD_FAILURE() << "accepted " << output;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.find('\n'), std::string::npos);
      EXPECT_NE(message.find(output), std::string::npos) << message;
      EXPECT_NE(message.find("is the input"), std::string::npos) << message;
    }
  }
  EXPECT_THROW(checkOutput(at("m.obj"), {at("link.obj")}), Error);  // the input named through a link
  checkOutput(at("new.sdf"), {at("m.obj")});
  checkOutput(at("other.obj"), {at("m.obj"), at("missing.obj")});
  EXPECT_EQ(readText(at("m.obj")), "v 0 0 0\n");
  EXPECT_EQ(snapshot(m_dir).size(), 4u);  // the writability probe left nothing
}

TEST_F(OutputFileTest, UnwritableOutputsFailWithOneLineNamingThem) {
  for (const std::string& output : {at("no/such/folder/x.sdf"), m_dir, std::string("")}) {
    try {
      checkOutput(output);
      ADD_FAILURE() << "accepted '" << output << "'";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.find('\n'), std::string::npos);
      EXPECT_NE(message.find(output.empty() ? "empty" : output), std::string::npos) << message;
    }
    EXPECT_THROW(OutputFile file(output), Error);
  }
}

TEST_F(OutputFileTest, ExceptionMidWriteLeavesOldTargetAndNoTemporaryFile) {
  writeText(at("field.sdf"), "old contents");
  try {
    OutputFile file(at("field.sdf"));
    file.stream() << std::string(200000, 'n');
    throw std::runtime_error("the build failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(readText(at("field.sdf")), "old contents");
  EXPECT_EQ(snapshot(m_dir).size(), 1u);
  EXPECT_EQ(detail::liveTempFileCount(), 0);
}

TEST_F(OutputFileTest, WriteErrorMidWriteLeavesOldTargetAndNoTemporaryFile) {
  // A file-size limit makes write(2) fail with EFBIG part way, like a full disk. In a child process, so the
  // limit does not outlive the test.
  writeText(at("field.sdf"), "old contents");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{100000, 100000};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    try {
      OutputFile file(at("field.sdf"));
      file.stream() << std::string(1000000, 'n');
      file.commit();
    } catch (const Error& e) {
      const std::string message = e.what();
      const bool named = message.find(at("field.sdf")) != std::string::npos;
      ::_exit(named && message.find('\n') == std::string::npos ? 0 : 2);
    }
    ::_exit(1);  // no error: the test fails
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(readText(at("field.sdf")), "old contents");
  EXPECT_EQ(snapshot(m_dir).size(), 1u);
}

/// Forks a child that writes `target` slowly, waits until its temporary file exists, sends `signalNumber`,
/// and returns the child's wait status.
int interruptSlowWriter(const std::string& target, int signalNumber) {
  int ready[2];
  if (::pipe(ready) != 0) return -1;
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(ready[0]);
    installTempFileCleanupHandlers();
    OutputFile file(target);
    for (int n = 0;; ++n) {
      file.stream() << std::string(4096, 'a') << std::flush;
      if (n == 0 && ::write(ready[1], "r", 1) != 1) ::_exit(4);
      ::usleep(1000);
    }
  }
  ::close(ready[1]);
  char byte = 0;
  const bool started = ::read(ready[0], &byte, 1) == 1;
  ::close(ready[0]);
  if (!started) return -1;
  ::usleep(20000);  // a few more slow writes
  ::kill(child, signalNumber);
  int status = 0;
  ::waitpid(child, &status, 0);
  return status;
}

TEST_F(OutputFileTest, SigtermDuringSlowWriteLeavesNoTemporaryFile) {
  writeText(at("frames.csv"), "previous run");
  const int status = interruptSlowWriter(at("frames.csv"), SIGTERM);
  ASSERT_TRUE(WIFSIGNALED(status)) << status;
  EXPECT_EQ(WTERMSIG(status), SIGTERM);  // the signal still ends the process, after the cleanup
  EXPECT_EQ(readText(at("frames.csv")), "previous run");
  EXPECT_EQ(snapshot(m_dir).size(), 1u);
}

TEST_F(OutputFileTest, SigintDuringSlowWriteLeavesNoTemporaryFile) {
  const int status = interruptSlowWriter(at("new.csv"), SIGINT);
  ASSERT_TRUE(WIFSIGNALED(status)) << status;
  EXPECT_EQ(WTERMSIG(status), SIGINT);
  EXPECT_TRUE(snapshot(m_dir).empty());
}

TEST_F(OutputFileTest, ASignalInAForkedChildLeavesTheParentsTemporaryFileAlone) {
  // Between fork and exec (gnuplot, ffmpeg) the child has our handler and a copy of the table: a signal to
  // the child alone must not remove the parent's files.
  installTempFileCleanupHandlers();
  OutputFile file(at("parent.csv"));
  file.stream() << "parent";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::raise(SIGTERM);
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  file.commit();
  EXPECT_EQ(readText(at("parent.csv")), "parent");
}

TEST_F(OutputFileTest, LongNamesStillFitTheTemporaryName) {
  const std::string name(250, 'n');
  writeOutputFile(at(name), "long");
  EXPECT_EQ(readText(at(name)), "long");
  EXPECT_EQ(snapshot(m_dir).size(), 1u);
}

TEST_F(OutputFileTest, CommitTwiceIsAnError) {
  OutputFile file(at("once.txt"));
  file.commit();
  EXPECT_THROW(file.commit(), Error);
  EXPECT_EQ(readText(at("once.txt")), "");
}

}  // namespace
}  // namespace sdfccd
