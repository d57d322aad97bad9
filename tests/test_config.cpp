// Service configuration: file and environment layers, with exact error texts.

#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>

#include "config/config.hpp"

namespace slosh::service {
namespace test_config {

std::string write_temp(const std::string& text) {
  // One file per call and per process: ctest runs the Config tests in parallel.
  static std::atomic<int> counter{0};
  const std::string path = ::testing::TempDir() + "slosh_config_test_" +
                           std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".json";
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Config, ShippedFileHoldsTheEmbeddedDefaults) {
  ServerConfig from_file;
  from_file.host = "x";
  from_file.port = 1;
  apply_config_file(std::string(SLOSH_SOURCE_DIR) + "/config/slosh.json", from_file);
  const ServerConfig defaults;
  EXPECT_EQ(from_file.host, defaults.host);
  EXPECT_EQ(from_file.port, defaults.port);
  EXPECT_EQ(from_file.workers, defaults.workers);
  EXPECT_EQ(from_file.queue, defaults.queue);
  EXPECT_EQ(from_file.cache_path, defaults.cache_path);
  EXPECT_EQ(from_file.cache_entries, defaults.cache_entries);
  EXPECT_EQ(from_file.solve_budget_s, defaults.solve_budget_s);
  EXPECT_EQ(from_file.queue_wait_s, defaults.queue_wait_s);
  EXPECT_EQ(from_file.max_body_bytes, defaults.max_body_bytes);
  EXPECT_EQ(from_file.batch_max, defaults.batch_max);
  EXPECT_EQ(from_file.http_threads, defaults.http_threads);
  EXPECT_EQ(from_file.cache_store_bytes, defaults.cache_store_bytes);
  EXPECT_EQ(from_file.cache_min_time_store_bytes, defaults.cache_min_time_store_bytes);
  EXPECT_EQ(from_file.cam_export_bytes, defaults.cam_export_bytes);
  EXPECT_EQ(from_file.log_format, defaults.log_format);
  EXPECT_EQ(from_file.replica_id, defaults.replica_id);
  EXPECT_EQ(from_file.cache_local, defaults.cache_local);
  EXPECT_EQ(from_file.cache_ttl_s, defaults.cache_ttl_s);
  EXPECT_EQ(from_file.redis_timeout_ms, defaults.redis_timeout_ms);
  EXPECT_EQ(from_file.redis_required, defaults.redis_required);
  EXPECT_EQ(from_file.batch_job_max, defaults.batch_job_max);
  EXPECT_EQ(from_file.batch_jobs_max, defaults.batch_jobs_max);
  EXPECT_EQ(from_file.batch_jobs_kept, defaults.batch_jobs_kept);
  EXPECT_EQ(from_file.batch_job_ttl_s, defaults.batch_job_ttl_s);
  EXPECT_EQ(from_file.batch_job_stale_s, defaults.batch_job_stale_s);
  EXPECT_EQ(from_file.batch_job_spread, defaults.batch_job_spread);
  EXPECT_EQ(from_file.batch_job_max_takes, defaults.batch_job_max_takes);
}

TEST(Config, LogFormatIsTextOrJson) {
  ServerConfig c;
  apply_environment({{"SLOSH_LOG_FORMAT", "json"}, {"SLOSH_REPLICA_ID", "line-3"}}, c);
  EXPECT_EQ(c.log_format, "json");
  EXPECT_EQ(c.replica_id, "line-3");
  apply_config_file(write_temp(R"({"log_format": "text"})"), c);
  EXPECT_EQ(c.log_format, "text");
  EXPECT_EQ(error_of([&] {
              apply_environment({{"SLOSH_LOG_FORMAT", "xml"}}, c);
            }),
            "SLOSH_LOG_FORMAT = xml is not a log format: allowed text, json");
  const std::string upper = write_temp(R"({"log_format": "JSON"})");
  EXPECT_EQ(error_of([&] { apply_config_file(upper, c); }),
            upper + ": log_format = JSON is not a log format: allowed text, json");
  const std::string number = write_temp(R"({"log_format": 1})");
  EXPECT_EQ(error_of([&] { apply_config_file(number, c); }),
            number + ": log_format = 1 is not a log format: allowed text, json");
  EXPECT_EQ(error_of([&] { apply_setting("log_format", "--log-format", "", c); }),
            "--log-format must be a non-empty text");
  EXPECT_EQ(c.log_format, "text");  // all or nothing
}

TEST(Config, RedisSettingsFromTheFileWithTheirTypes) {
  ServerConfig c;
  apply_config_file(write_temp(R"({"cache": "redis://:pw@10.0.0.5:6380/1", "cache_local":
      "local.sqlite", "cache_ttl_s": 86400, "redis_timeout_ms": 250, "redis_required": true})"),
                    c);
  EXPECT_EQ(c.cache_path, "redis://:pw@10.0.0.5:6380/1");
  EXPECT_EQ(c.cache_local, "local.sqlite");
  EXPECT_EQ(c.cache_ttl_s, 86400u);
  EXPECT_EQ(c.redis_timeout_ms, 250u);
  EXPECT_TRUE(c.redis_required);
  const std::string quoted = write_temp(R"({"redis_required": "true"})");
  EXPECT_EQ(error_of([&] { apply_config_file(quoted, c); }),
            quoted + ": redis_required = \"true\" has the wrong type: allowed true or false");
  const std::string zero = write_temp(R"({"redis_timeout_ms": 0})");
  EXPECT_EQ(error_of([&] { apply_config_file(zero, c); }),
            zero + ": redis_timeout_ms = 0 is out of range: allowed 1 to 60000");
  const std::string bad = write_temp(R"({"cache": "redis://10.0.0.5:6380/99"})");
  EXPECT_EQ(error_of([&] { apply_config_file(bad, c); }),
            bad +
                ": cache = redis://10.0.0.5:6380/99 is not a Redis URL: the database '99' is not "
                "a number from 0 to 15 (expected redis://host:port/db or "
                "redis://:password@host:port/db)");
}

TEST(Config, EnvironmentOverridesTheFile) {
  ServerConfig c;
  apply_config_file(write_temp(R"({"host": "0.0.0.0", "port": 9000})"), c);
  EXPECT_EQ(c.host, "0.0.0.0");
  EXPECT_EQ(c.port, 9000);
  apply_environment({{"SLOSH_PORT", "9100"}}, c);
  EXPECT_EQ(c.host, "0.0.0.0");
  EXPECT_EQ(c.port, 9100);
  apply_environment({{"SLOSH_HOST", "::1"}, {"SLOSH_PORT", ""}}, c);
  EXPECT_EQ(c.host, "::1");
  EXPECT_EQ(c.port, 9100);
  apply_config_file(write_temp(R"({"workers": 3, "queue": 5, "cache": ""})"), c);
  apply_environment({{"SLOSH_QUEUE", "7"}, {"SLOSH_CACHE", "/tmp/p.sqlite"}}, c);
  EXPECT_EQ(c.workers, 3u);
  EXPECT_EQ(c.queue, 7u);
  EXPECT_EQ(c.cache_path, "/tmp/p.sqlite");
}

TEST(Config, ErrorsNameTheSettingAndTheAllowedValues) {
  ServerConfig c;
  const std::string path = write_temp(R"({"port": 70000})");
  EXPECT_EQ(error_of([&] { apply_config_file(path, c); }),
            path + ": port = 70000 is out of range: allowed 0 to 65535");
  const std::string typo = write_temp(R"({"prot": 80})");
  EXPECT_EQ(
      error_of([&] { apply_config_file(typo, c); }),
      typo +
          ": prot is not a known setting; allowed: host, port, workers, queue, cache, "
          "cache_local, cache_ttl_s, redis_timeout_ms, redis_required, cache_entries, "
          "solve_budget_s, queue_wait_s, max_body_bytes, batch_max, "
          "max_response_bytes, http_threads, read_timeout_s, write_timeout_s, "
          "keep_alive_timeout_s, "
          "request_timeout_s, cache_memory_bytes, cache_store_bytes, "
          "cache_min_time_store_bytes, cam_export_bytes, log_format, replica_id, batch_job_max, "
          "batch_jobs_max, batch_jobs_kept, batch_jobs_bytes, batch_job_ttl_s, batch_job_stale_s, "
          "batch_job_spread, batch_job_max_takes");
  const std::string queue = write_temp(R"({"queue": 0})");
  EXPECT_EQ(error_of([&] { apply_config_file(queue, c); }),
            queue + ": queue = 0 is out of range: allowed 1 to 100000");
  EXPECT_EQ(error_of([&] {
              apply_environment({{"SLOSH_BATCH_JOBS_BYTES", "65535"}}, c);
            }),
            "SLOSH_BATCH_JOBS_BYTES = 65535 is out of range: allowed 65536 to "
            "1099511627776");
  EXPECT_EQ(error_of([&] {
              apply_environment({{"SLOSH_SOLVE_BUDGET_S", "0"}}, c);
            }),
            "SLOSH_SOLVE_BUDGET_S = 0 is out of range: allowed > 0.0 and <= 600.0 s");
  // A number outside the range is out of range; only text that is no number is not a duration.
  EXPECT_EQ(error_of([&] {
              apply_environment({{"SLOSH_BATCH_JOB_STALE_S", "1"}}, c);
            }),
            "SLOSH_BATCH_JOB_STALE_S = 1 is out of range: allowed > 1.0 and <= 86400.0 s");
  EXPECT_EQ(error_of([&] {
              apply_environment({{"SLOSH_BATCH_JOB_STALE_S", "1s"}}, c);
            }),
            "SLOSH_BATCH_JOB_STALE_S = 1s is not a duration: allowed > 1.0 and <= 86400.0 s");
  EXPECT_EQ(error_of([&] {
              apply_environment({{"SLOSH_BATCH_JOB_STALE_S", "nan"}}, c);
            }),
            "SLOSH_BATCH_JOB_STALE_S = nan is not a duration: allowed > 1.0 and <= 86400.0 s");
  const std::string text_port = write_temp(R"({"port": "80"})");
  EXPECT_EQ(error_of([&] { apply_config_file(text_port, c); }),
            text_port + ": port = \"80\" is not a TCP port: allowed 0 to 65535");
  EXPECT_EQ(error_of([&] {
              apply_environment({{"SLOSH_PORT", "80x"}}, c);
            }),
            "SLOSH_PORT = 80x is not a TCP port: allowed 0 to 65535");
  EXPECT_EQ(error_of([&] { apply_config_file("/nonexistent/slosh.json", c); }),
            "cannot read config file '/nonexistent/slosh.json'");
  EXPECT_EQ(c.port, 8080);  // nothing applied by the failed layers
  EXPECT_EQ(c.queue, 64u);
}

}  // namespace test_config
}  // namespace slosh::service
