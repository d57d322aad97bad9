// The Redis client of the shared cache (service/storage/redis_client.hpp) against a real
// redis-server on a loopback port: URL parsing with its exact refusals, commands, a stopped
// (SIGSTOP) server that makes commands time out, back-off, and recovery after SIGCONT and after a
// restart.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "config/config.hpp"
#include "storage/redis_client.hpp"
#include "support/redis_server.hpp"

namespace test_redis_client {

using slosh::service::parse_redis_url;
using slosh::service::RedisClient;
using slosh::service::RedisOptions;
using slosh::service::RedisReply;
using slosh::test::RedisServer;
using namespace std::chrono_literals;

std::string refusal(const std::string& url) {
  try {
    (void)parse_redis_url(url);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

RedisOptions options_for(const RedisServer& server, std::chrono::milliseconds retry = 100ms) {
  return RedisOptions{.url = parse_redis_url(server.url()),
                      .timeout = 200ms,
                      .retry_interval = retry,
                      .connections = 2};
}

/// Polls `client` with PING until it answers (true) or 5 s passed (false).
bool answers_within_5s(RedisClient& client) {
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (std::chrono::steady_clock::now() < deadline) {
    if (const auto r = client.command({"PING"}); r && r->text == "PONG") return true;
    std::this_thread::sleep_for(20ms);
  }
  return false;
}

TEST(RedisUrl, ParsesHostPortDatabaseAndPassword) {
  const auto full = parse_redis_url("redis://10.0.0.5:6380/3");
  EXPECT_EQ(full.host, "10.0.0.5");
  EXPECT_EQ(full.port, 6380);
  EXPECT_EQ(full.db, 3);
  EXPECT_EQ(full.password, "");
  const auto defaults = parse_redis_url("redis://cache");
  EXPECT_EQ(defaults.host, "cache");
  EXPECT_EQ(defaults.port, 6379);
  EXPECT_EQ(defaults.db, 0);
  EXPECT_EQ(parse_redis_url("redis://cache/").db, 0);
  const auto secret = parse_redis_url("redis://:s3cr:et@cache:7000/15");
  EXPECT_EQ(secret.password, "s3cr:et");
  EXPECT_EQ(secret.port, 7000);
  EXPECT_EQ(secret.db, 15);
  EXPECT_EQ(secret.display(), "redis://:***@cache:7000/15");
  const auto v6 = parse_redis_url("redis://[::1]:7001/2");
  EXPECT_EQ(v6.host, "::1");
  EXPECT_EQ(v6.port, 7001);
  EXPECT_EQ(v6.display(), "redis://[::1]:7001/2");
}

TEST(RedisUrl, RefusesBadValuesNamingThem) {
  const std::string expected = " (expected redis://host:port/db or redis://:password@host:port/db)";
  EXPECT_EQ(
      refusal("redis://h:x/0"),
      "redis://h:x/0 is not a Redis URL: the port 'x' is not a number from 1 to 65535" + expected);
  EXPECT_EQ(
      refusal("redis://h:/0"),
      "redis://h:/0 is not a Redis URL: the port '' is not a number from 1 to 65535" + expected);
  EXPECT_EQ(refusal("redis://h:65536"),
            "redis://h:65536 is not a Redis URL: the port '65536' is not a number from 1 to 65535" +
                expected);
  EXPECT_EQ(refusal("redis://h:6379/16"),
            "redis://h:6379/16 is not a Redis URL: the database '16' is not a number from 0 to 15" +
                expected);
  EXPECT_EQ(refusal("redis://h:6379/a"),
            "redis://h:6379/a is not a Redis URL: the database 'a' is not a number from 0 to 15" +
                expected);
  EXPECT_EQ(refusal("redis:///0"), "redis:///0 is not a Redis URL: the host is empty" + expected);
  EXPECT_EQ(refusal("redis://h:6379/0?timeout=1"),
            "redis://h:6379/0?timeout=1 is not a Redis URL: query parameters and fragments are "
            "not supported" +
                expected);
  EXPECT_EQ(refusal("rediss://h:6379/0"),
            "rediss://h:6379/0 is not a Redis URL: it does not start with redis://" + expected);
  // The password never appears in a message.
  EXPECT_EQ(refusal("redis://:hunter2@h:0/0"),
            "redis://:***@h:0/0 is not a Redis URL: the port '0' is not a number from 1 to 65535" +
                expected);
  EXPECT_EQ(refusal("redis://admin:hunter2@h/0"),
            "redis://admin:***@h/0 is not a Redis URL: a user name is not supported (write the "
            "password as ':password@')" +
                expected);
}

TEST(RedisUrl, ConfigLayersRefuseABadCacheNamingTheLayer) {
  slosh::service::ServerConfig config;
  try {
    slosh::service::apply_environment({{"SLOSH_CACHE", "redis://h:x/0"}}, config);
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "SLOSH_CACHE = redis://h:x/0 is not a Redis URL: the port 'x' is not a number from "
              "1 to 65535 (expected redis://host:port/db or redis://:password@host:port/db)");
  }
  try {
    slosh::service::apply_environment({{"SLOSH_CACHE", "http://h:6379"}}, config);
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "SLOSH_CACHE = http://h:6379 is neither a SQLite file nor a Redis URL: the only URL "
              "scheme supported is redis://");
  }
  config.cache_local = "local.sqlite";
  try {
    slosh::service::check_cache_levels(config);
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "cache_local = local.sqlite needs a Redis cache (cache = redis://host:port/db), but "
              "cache = '${XDG_STATE_HOME}/slosh/plans.sqlite': set the SQLite file as cache alone, "
              "or cache to a "
              "Redis URL");
  }
  slosh::service::apply_environment({{"SLOSH_CACHE", "redis://127.0.0.1:6390/1"},
                                     {"SLOSH_CACHE_TTL_S", "3600"},
                                     {"SLOSH_REDIS_TIMEOUT_MS", "150"},
                                     {"SLOSH_REDIS_REQUIRED", "true"}},
                                    config);
  EXPECT_NO_THROW(slosh::service::check_cache_levels(config));
  EXPECT_EQ(slosh::service::local_cache_path(config), "local.sqlite");
  EXPECT_EQ(slosh::service::redis_cache_url(config), "redis://127.0.0.1:6390/1");
  EXPECT_EQ(config.cache_ttl_s, 3600u);
  EXPECT_EQ(config.redis_timeout_ms, 150u);
  EXPECT_TRUE(config.redis_required);
  try {
    slosh::service::apply_environment({{"SLOSH_REDIS_REQUIRED", "yes"}}, config);
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "SLOSH_REDIS_REQUIRED = yes is not a boolean: allowed true, false, 1, 0");
  }
}

TEST(RedisClient, RunsCommandsBinarySafeAndPipelined) {
  const RedisServer server;
  RedisClient client(options_for(server));
  EXPECT_TRUE(client.state().up);
  const std::string value("a\0b\r\nc", 6);
  ASSERT_TRUE(client.command({"SET", "k", value}));
  const auto got = client.command({"GET", "k"});
  ASSERT_TRUE(got);
  EXPECT_EQ(got->type, RedisReply::Type::kString);
  EXPECT_EQ(got->text, value);
  EXPECT_EQ(client.command({"GET", "absent"})->type, RedisReply::Type::kNil);
  const auto replies = client.pipeline({{"RPUSH", "l", "x", "y"}, {"LRANGE", "l", "0", "-1"}});
  ASSERT_TRUE(replies);
  ASSERT_EQ(replies->size(), 2u);
  EXPECT_EQ((*replies)[0].integer, 2);
  ASSERT_EQ((*replies)[1].elements.size(), 2u);
  EXPECT_EQ((*replies)[1].elements[1].text, "y");
  // An error reply is an answer: Redis is still up.
  const auto wrong = client.command({"INCR", "l"});
  ASSERT_TRUE(wrong);
  EXPECT_TRUE(wrong->is_error());
  EXPECT_TRUE(client.state().up);
}

TEST(RedisClient, ConnectionsAreSharedSafelyByThreads) {
  const RedisServer server;
  // Sharing is what is checked, not the deadline (the SIGSTOP tests do that): on a loaded machine
  // eight threads queued on two connections can wait past 200 ms, and a missed deadline would then
  // mark the client down for the retry interval and fail the commands behind it.
  RedisOptions options = options_for(server);
  options.timeout = 10s;
  RedisClient client(options);
  std::atomic<int> failures{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 200; ++i) {
        const auto r = client.command({"INCR", "counter"});
        if (!r || r->type != RedisReply::Type::kInteger) ++failures;
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(failures, 0);
  EXPECT_EQ(client.command({"GET", "counter"})->text, "1600");
}

TEST(RedisClient, SelectsTheDatabaseAndAuthenticates) {
  const RedisServer server({"--requirepass", "pw"});
  RedisOptions good = options_for(server);
  good.url = parse_redis_url("redis://:pw@127.0.0.1:" + std::to_string(server.port()) + "/2");
  RedisClient client(good);
  ASSERT_TRUE(client.command({"SET", "in2", "yes"}));
  good.url.db = 0;
  RedisClient db0(good);
  EXPECT_EQ(db0.command({"GET", "in2"})->type, RedisReply::Type::kNil);
  RedisOptions bad = good;
  bad.url.password = "wrong";
  RedisClient refused(bad);
  EXPECT_FALSE(refused.command({"PING"}));
  EXPECT_FALSE(refused.state().up);
  EXPECT_TRUE(refused.state().error.starts_with("authentication failed: "))
      << refused.state().error;
}

TEST(RedisClient, NoServerStartsDownWithoutThrowing) {
  int port = 0;
  {
    const RedisServer server;
    port = server.port();
  }  // killed: nothing listens on the port now
  RedisOptions options;
  options.url = parse_redis_url("redis://127.0.0.1:" + std::to_string(port) + "/0");
  RedisClient client(options);
  EXPECT_FALSE(client.state().up);
  EXPECT_EQ(client.state().error, "cannot connect: Connection refused");
  EXPECT_FALSE(client.command({"PING"}));
}

TEST(RedisClient, StoppedServerTimesOutThenBacksOffAndRecovers) {
  RedisServer server;
  RedisClient slow_retry(options_for(server, 60s));
  RedisClient fast_retry(options_for(server, 100ms));
  ASSERT_TRUE(slow_retry.state().up);
  ASSERT_TRUE(fast_retry.state().up);
  server.pause();
  // A stopped server accepts nothing and answers nothing: the command gives up at its timeout
  // (the bound is generous; without a timeout the call would never return).
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(slow_retry.command({"SET", "k", "v"}));
  EXPECT_LT(std::chrono::steady_clock::now() - start, 3s);
  EXPECT_FALSE(slow_retry.state().up);
  EXPECT_EQ(slow_retry.state().error, "no reply within 200 ms");
  EXPECT_FALSE(fast_retry.command({"PING"}));
  server.resume();
  // Backing off: the server answers again, but the client does not ask it before its retry
  // interval (60 s) has passed.
  ASSERT_TRUE(server.ping());
  EXPECT_FALSE(slow_retry.command({"PING"}));
  EXPECT_FALSE(slow_retry.state().up);
  // The other client retries every 100 ms and finds it again by itself.
  EXPECT_TRUE(answers_within_5s(fast_retry));
  EXPECT_TRUE(fast_retry.state().up);
  EXPECT_EQ(fast_retry.state().error, "");
}

TEST(RedisClient, RecoversAfterARestartOnTheSamePort) {
  RedisServer server;
  RedisClient client(options_for(server));
  ASSERT_TRUE(client.command({"SET", "before", "1"}));
  server.kill();
  EXPECT_FALSE(client.command({"GET", "before"}));
  EXPECT_FALSE(client.state().up);
  EXPECT_FALSE(client.state().error.empty());
  server.start();
  EXPECT_TRUE(answers_within_5s(client));
  EXPECT_TRUE(client.state().up);
  // A new server (nothing persisted): the old connections were replaced, the key is gone.
  EXPECT_EQ(client.command({"GET", "before"})->type, RedisReply::Type::kNil);
}

}  // namespace test_redis_client
