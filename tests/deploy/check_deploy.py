#!/usr/bin/env python3
"""Structural checks of deploy/ where no linter is packaged (hadolint, kubeconform): yamllint on the
compose file and the manifests; deploy/compose.yaml against deploy/nginx.conf (the upstream servers
are the slosh services at their ports, the proxy mounts the config its image runs, ports agree);
the Containerfile's runtime stage (non-root USER, only the binary copied, the port exposed); the
Kubernetes manifests (probes, non-root read-only pods, ports, the ConfigMap's config keys = those
of config/slosh.json, the Redis Service the config names); deploy/nginx-slosh.conf with the same
limits as deploy/nginx.conf. Exit 0 when every check holds; else prints each failure, exit 1.
Uses python3-yaml (a dependency of Debian's yamllint)."""

import argparse
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import yaml

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)


def flag(command, name):
    """The value after `name` in an argument list, or None."""
    return command[command.index(name) + 1] if name in command else None


def nginx_directives(text):
    """(directive, value) pairs of an nginx config, comments dropped, in order."""
    text = re.sub(r"#[^\n]*", "", text)
    return [(m.group(1), m.group(2).strip()) for m in re.finditer(r"(\w+)\s+([^;{}]*);", text)]


def check_yamllint(root):
    if shutil.which("yamllint") is None:
        print("yamllint not installed: lint skipped")
        return
    config = "{extends: default, rules: {line-length: {max: 100}}}"
    paths = [str(root / "deploy/compose.yaml"), str(root / "deploy/k8s")]
    run = subprocess.run(["yamllint", "-s", "-d", config, *paths], capture_output=True, text=True)
    check(run.returncode == 0, "yamllint:\n" + run.stdout + run.stderr)


def check_compose(root, nginx):
    compose = yaml.safe_load((root / "deploy/compose.yaml").read_text())
    services = compose["services"]
    replicas = {n: s for n, s in services.items() if s.get("build", {}).get("target") == "runtime"}
    check(len(replicas) == 3, f"compose: 3 slosh replicas expected, found {sorted(replicas)}")
    check("redis" in services, "compose: no redis service")
    upstream = re.search(r"upstream slosh \{(.*?)\}", nginx, re.S).group(1)
    servers = {d[1].split()[0] for d in nginx_directives(upstream) if d[0] == "server"}
    expected = set()
    for name, service in replicas.items():
        command = [str(c) for c in service["command"]]
        check(command[0] == "serve", f"compose {name}: command is not serve")
        check(flag(command, "--host") == "0.0.0.0", f"compose {name}: not bound to 0.0.0.0")
        check(flag(command, "--replica-id") == name, f"compose {name}: --replica-id is not {name}")
        cache = flag(command, "--cache") or ""
        check(cache.startswith("redis://redis:6379/"), f"compose {name}: cache is not the redis")
        expected.add(f"{name}:{flag(command, '--port')}")
        health = " ".join(service["healthcheck"]["test"])
        check(f"/dev/tcp/127.0.0.1/{flag(command, '--port')}" in health and "/readyz" in health,
              f"compose {name}: healthcheck does not ask /readyz on its port")
        check(service.get("read_only") is True, f"compose {name}: root file system not read-only")
        check("ports" not in service, f"compose {name}: a replica publishes a port")
    check(servers == expected, f"nginx upstream {sorted(servers)} != compose replicas {sorted(expected)}")
    proxy = services["proxy"]
    check(proxy["build"]["target"] == "proxy", "compose proxy: not the proxy stage")
    mounts = {v.split(":")[1]: v.split(":")[0] for v in proxy["volumes"]}
    check(mounts.get("/etc/nginx/slosh.conf") == "./nginx.conf",
          "compose proxy: deploy/nginx.conf is not mounted at /etc/nginx/slosh.conf")
    listen = [d[1] for d in nginx_directives(nginx) if d[0] == "listen"]
    published = [p.split(":")[-1] for p in proxy["ports"]]
    check(listen == published, f"nginx listens on {listen}, compose publishes {published}")
    check("/healthz" in " ".join(proxy["healthcheck"]["test"]), "compose proxy: no /healthz check")
    check(all(s.get("depends_on", {}).get(n, {}).get("condition") == "service_healthy"
              for s in [proxy] for n in replicas), "compose proxy: does not wait for the replicas")


def containerfile_stages(text):
    stages = []
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("FROM "):
            stages.append({"from": line, "lines": []})
        elif stages and line and not line.startswith("#"):
            stages[-1]["lines"].append(line)
    return stages


def check_containerfile(root):
    text = (root / "deploy/Containerfile").read_text()
    stages = containerfile_stages(text)
    check([s["from"].split()[-1] for s in stages] == ["build", "proxy", "runtime"],
          "Containerfile: stages build, proxy, runtime (the default, last) expected")
    check(all(s["from"].split()[1].startswith("docker.io/library/debian:12") for s in stages),
          "Containerfile: every stage on debian:12")
    build, proxy, runtime = stages
    check(any("--target slosh" in l for l in build["lines"]), "Containerfile: build stage builds more than slosh")
    copies = [l for l in runtime["lines"] if l.startswith(("COPY", "ADD"))]
    check(copies == ["COPY --from=build /build/slosh /usr/local/bin/slosh"],
          f"Containerfile runtime: copies {copies}, expected only the binary")
    users = [l.split()[1] for l in runtime["lines"] if l.startswith("USER ")]
    check(len(users) == 1 and users[0].split(":")[0] not in ("0", "root"),
          f"Containerfile runtime: USER {users} is not one non-root user")
    check(not any(l.startswith("HEALTHCHECK") for s in stages for l in s["lines"]),
          "Containerfile: HEALTHCHECK is dropped by OCI images (see its comment)")
    check("EXPOSE 8080" in runtime["lines"], "Containerfile runtime: does not expose 8080")
    check(any(l.startswith("VOLUME") and "/var/lib/slosh" in l for l in runtime["lines"]),
          "Containerfile runtime: the state directory is not a volume")
    cmd = [l for l in proxy["lines"] if l.startswith("CMD")]
    check(cmd and "/etc/nginx/slosh.conf" in cmd[0] and "daemon off;" in cmd[0],
          "Containerfile proxy: does not run /etc/nginx/slosh.conf in the foreground")


def check_k8s(root):
    docs = []
    for path in sorted((root / "deploy/k8s").glob("*.yaml")):
        docs += [d for d in yaml.safe_load_all(path.read_text()) if d and "metadata" in d]
    by_kind = {}
    for d in docs:
        by_kind.setdefault(d["kind"], {})[d["metadata"]["name"]] = d
    deployment = by_kind["Deployment"]["slosh"]
    pod = deployment["spec"]["template"]["spec"]
    container = pod["containers"][0]
    check(container["readinessProbe"]["httpGet"]["path"] == "/readyz", "k8s: readiness is not /readyz")
    check(container["livenessProbe"]["httpGet"]["path"] == "/healthz", "k8s: liveness is not /healthz")
    check(pod["securityContext"]["runAsNonRoot"] is True and pod["securityContext"]["runAsUser"] != 0,
          "k8s: pod not non-root")
    check(container["securityContext"]["readOnlyRootFilesystem"] is True, "k8s: root fs writable")
    check(container["securityContext"]["allowPrivilegeEscalation"] is False, "k8s: escalation")
    check({"requests", "limits"} <= set(container["resources"]), "k8s: resources incomplete")
    config_map = by_kind["ConfigMap"]["slosh-config"]
    config = json.loads(config_map["data"]["slosh.json"])
    shipped = json.loads((root / "config/slosh.json").read_text())
    check(set(config) == set(shipped),
          f"k8s ConfigMap keys differ from config/slosh.json: {set(config) ^ set(shipped)}")
    port = container["ports"][0]
    check(port["containerPort"] == config["port"], "k8s: containerPort != config port")
    check(config["host"] == "0.0.0.0", "k8s: config not bound to 0.0.0.0")
    check(config.get("batch_job_spread") == "helpers",
          "k8s: batch_job_spread is not \"helpers\": the replicas would not help a job nor take "
          "over a dead replica's job")
    check(flag(container["args"], "--config") == "/etc/slosh/slosh.json" and
          any(m["mountPath"] == "/etc/slosh" for m in container["volumeMounts"]),
          "k8s: the ConfigMap is not the config file")
    service = by_kind["Service"]["slosh"]
    check(service["spec"]["ports"][0]["targetPort"] == port["name"], "k8s: Service targetPort")
    check(service["spec"]["selector"] == deployment["spec"]["selector"]["matchLabels"],
          "k8s: Service selects other pods")
    redis_host = re.match(r"redis://([^:/]+):(\d+)/", config["cache"])
    check(redis_host is not None and redis_host.group(1) in by_kind["Service"],
          f"k8s: cache {config['cache']} names no Service")
    check("slosh-redis" in by_kind["Deployment"], "k8s: no Redis Deployment")


def check_nginx_pair(root, nginx):
    single = nginx_directives((root / "deploy/nginx-slosh.conf").read_text())
    replicas = nginx_directives(nginx)
    for name in ("client_header_timeout", "client_body_timeout", "send_timeout",
                 "keepalive_timeout", "client_max_body_size", "large_client_header_buffers",
                 "limit_conn", "limit_req", "limit_req_zone", "limit_conn_zone",
                 "proxy_read_timeout", "proxy_connect_timeout", "limit_req_status"):
        a = [v for d, v in single if d == name]
        b = [v for d, v in replicas if d == name]
        # keepalive_timeout appears in the upstream too in nginx.conf: compare the server's.
        check(a and a[0] in b, f"nginx-slosh.conf {name} {a} not in nginx.conf {b}")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--root", default=Path(__file__).resolve().parents[2], type=Path)
    root = parser.parse_args().root
    nginx = (root / "deploy/nginx.conf").read_text()
    check_yamllint(root)
    check_compose(root, nginx)
    check_containerfile(root)
    check_k8s(root)
    check_nginx_pair(root, nginx)
    for f in failures:
        print("FAIL:", f)
    print(f"deploy checks: {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
