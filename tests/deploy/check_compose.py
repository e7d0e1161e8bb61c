#!/usr/bin/env python3
"""Keeps docker/compose.yaml true without a Docker engine (`docker compose config` cannot run here).

  check_compose.py REPO_ROOT

Checks that the YAML parses and that the pieces agree with each other and with the repository:
two `mocapd serve` replicas built from docker/Dockerfile over one store folder (mounted read-only
only with `mocapd serve --read-only`),
and an nginx service that renders docker/nginx-grpc.conf (the template the two-replica test runs)
with every ${MOCAP_*} variable the template uses, pointing at the replicas' listening ports.
"""
import os
import re
import sys

import yaml


def fail(message):
    print(f"FAIL: docker/compose.yaml: {message}", file=sys.stderr)
    sys.exit(1)


def expect(condition, message):
    if not condition:
        fail(message)


def option(command, name):
    expect(name in command, f"command {command} lacks {name}")
    index = command.index(name)
    expect(index + 1 < len(command), f"{name} has no value in {command}")
    return command[index + 1]


def interpolate(value):
    """Compose's ${VAR:-default} / ${VAR-default} / ${VAR} with the environment unset: the default."""
    return re.sub(r"\$\{([A-Za-z_][A-Za-z0-9_]*)(?::?-([^}]*))?\}", lambda m: m.group(2) or "", value)


def main():
    root = sys.argv[1]
    docker = os.path.join(root, "docker")
    with open(os.path.join(docker, "compose.yaml"), encoding="utf-8") as stream:
        compose = yaml.safe_load(stream)
    expect(isinstance(compose, dict), "not a mapping")
    services = compose.get("services")
    expect(isinstance(services, dict), "no services")

    replicas = {name: s for name, s in services.items()
                if isinstance(s.get("command"), list) and s["command"][:1] == ["serve"]}
    expect(len(replicas) == 2, f"expected two `mocapd serve` replicas, found {sorted(replicas)}")
    stores, ports, read_only = set(), {}, set()
    for name, service in replicas.items():
        build = service.get("build")
        expect(isinstance(build, dict), f"{name}: no build section")
        context = os.path.normpath(os.path.join(docker, build.get("context", ".")))
        dockerfile = os.path.join(context, build.get("dockerfile", "Dockerfile"))
        expect(os.path.isfile(dockerfile), f"{name}: no Dockerfile at {dockerfile}")
        with open(dockerfile, encoding="utf-8") as stream:
            expect('ENTRYPOINT ["mocapd"]' in stream.read(), f"{name}: {dockerfile} does not run mocapd")
        command = [str(part) for part in service["command"]]
        store = interpolate(option(command, "--store"))
        listen = option(command, "--listen")
        expect(re.fullmatch(r"0\.0\.0\.0:\d+", listen), f"{name}: --listen {listen} is not 0.0.0.0:PORT")
        ports[name] = listen.split(":")[1]
        volumes = service.get("volumes", [])
        mounts = [v for v in volumes if isinstance(v, dict) and store.startswith(v.get("target", "//") + "/")]
        expect(len(mounts) == 1, f"{name}: the store {store} is not on exactly one long-syntax mount")
        # A read-only store folder needs a read-only server (SQLite cannot open a WAL store where
        # it cannot create the -shm file): `mocapd serve --read-only` (docs/deployment.md "Scaling out").
        expect(mounts[0].get("read_only") is not True or "--read-only" in command,
               f"{name}: the store is mounted read_only but `mocapd serve` lacks --read-only (it would not start)")
        read_only.add(mounts[0].get("read_only") is True)
        stores.add((mounts[0].get("source"), store))
        expect(service.get("ports") is None, f"{name}: a replica publishes a port (only nginx should)")
    expect(len(stores) == 1, f"the replicas do not share one store: {stores}")
    expect(len(read_only) == 1, "one replica mounts the store read-only, the other read-write")

    nginx = [s for s in services.values() if str(s.get("image", "")).startswith("nginx")]
    expect(len(nginx) == 1, "expected one nginx service")
    nginx = nginx[0]
    templates = [v for v in nginx.get("volumes", []) if isinstance(v, dict)
                 and str(v.get("target", "")).startswith("/etc/nginx/templates/")
                 and str(v.get("target", "")).endswith(".template")]
    expect(len(templates) == 1, "nginx does not mount a template into /etc/nginx/templates/")
    template_path = os.path.normpath(os.path.join(docker, templates[0]["source"]))
    expect(template_path == os.path.join(docker, "nginx-grpc.conf"),
           f"nginx's template is {template_path}, not docker/nginx-grpc.conf (the one the test runs)")
    with open(template_path, encoding="utf-8") as stream:
        template = stream.read()
    used = set(re.findall(r"\$\{(MOCAP_[A-Z0-9_]+)\}", template))
    environment = nginx.get("environment", {})
    if isinstance(environment, list):
        environment = dict(item.split("=", 1) for item in environment)
    expect(used and used <= set(environment), f"nginx's environment lacks {sorted(used - set(environment))}")
    upstreams = sorted(str(environment[v]) for v in used if v.startswith("MOCAP_REPLICA_"))
    expected = sorted(f"{name}:{port}" for name, port in ports.items())
    expect(upstreams == expected, f"nginx's upstreams {upstreams} are not the replicas {expected}")
    listen = str(environment["MOCAP_LISTEN"])
    published = [str(p) for p in nginx.get("ports", [])]
    expect(any(p.endswith(":" + listen.split(":")[-1]) for p in published),
           f"nginx listens on {listen} but publishes {published}")
    depends = nginx.get("depends_on", [])
    expect(set(replicas) <= set(depends), "nginx does not depend on both replicas (it resolves them at start)")
    print(f"docker/compose.yaml: ok (replicas {sorted(replicas)}, nginx upstreams {upstreams})")


if __name__ == "__main__":
    main()
