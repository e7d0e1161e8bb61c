#!/usr/bin/env python3
"""The Reconstruction service from the Python client (package mocap_client), checked against the
C++ SDK.

  python_reconstruct_test.py --address HOST:PORT --key KEY --database NAME --csv WRISTS.csv \
      --cxx-json CXX.json --lag D --k1 K1 --k2 K2 [--example-json EX.json --example-cxx-json CXX5.json]

Run with a Python that has mocap_client installed (python_reconstruct_test.sh installs the
build's into a venv). CXX.json is what `mocap reconstruct --csv WRISTS.csv --lag D --k1 K1 --k2 K2
--diagnostics -o CXX` wrote for the same input and config; EX.json what
client/python/examples/stream_csv.py wrote for the CSV and CXX5.json what `mocap reconstruct --csv
WRISTS.csv --lag 5 -o CXX5` wrote. Checks:
  - mocap_client.read_wrist_csv reads the CSV (and refuses a bad header, a bad number and a
    confidence out of range with the file and line);
  - a Reconstruct stream through mocap_client.Client (config with fixed_lag and
    include_diagnostics, the CSV's samples, finish) ends OK with `started` first, then frames,
    then `summary` last; once with the CLI's 30 samples per message and once with one sample per
    message;
  - its frames equal the C++ SDK's: index, segment, time, root position and every rotation
    within 1e-5 (and the pelvis, ankles, wrists and diagnostics);
  - ReconstructTrajectory (unary) gives the same frames;
  - the example's JSON is the C++ CLI's: the same fields, skeleton, summary counts and frames;
  - errors map to the documented codes (UNAUTHENTICATED without a key, NOT_FOUND for a database
    that is not there, INVALID_ARGUMENT for samples before the config);
  - ServerStatus.GetMetrics counts the sessions;
  - standard gRPC health checking answers SERVING and server reflection lists our services (both
    called as raw methods on their wire format, as a generic tool such as grpcurl would).
"""
import argparse
import json
import math
import sys

import grpc
from google.protobuf import json_format

import mocap_client
from mocap_client.v1 import reconstruction_pb2 as rpb
from mocap_client.v1 import reconstruction_pb2_grpc as rgrpc
from interop_checks import check, expect_error, failures, reflected_services, verdict

TOLERANCE = 1e-5


def parse_args():
    parser = argparse.ArgumentParser()
    for name in ("--address", "--key", "--database", "--csv", "--cxx-json"):
        parser.add_argument(name, required=True)
    parser.add_argument("--lag", type=int, required=True)
    parser.add_argument("--k1", type=int, required=True)
    parser.add_argument("--k2", type=int, required=True)
    parser.add_argument("--example-json", help="what examples/stream_csv.py wrote")
    parser.add_argument("--example-cxx-json", help="what `mocap reconstruct --lag 5` wrote for the same CSV")
    parser.add_argument("--sessions-before", type=int, default=1,
                        help="Reconstruct sessions the server ran before this script (the C++ ones, the example)")
    return parser.parse_args()


args = parse_args()


def check_csv_errors():
    """The CSV reader refuses what the C++ one refuses, naming the line."""
    header = "time,left_x,left_y,left_z,right_x,right_y,right_z,left_confidence,right_confidence\n"
    for lines, expected in (
            (["time,left_x,left_y\n"], "<csv>:1: expected the header"),
            (["# a comment\n", header, "\n", "0.0,0,1,0,0,1,x,,\n"], '<csv>:4: right_z is not a number: "x"'),
            ([header, "0.0,0,1,0,0,1,0,1.5,\n"], "<csv>:2: left_confidence must lie in 0..1"),
            ([header, "0.0,0,1,0,0,1,0\n"], "<csv>:2: expected 9 fields as in the header, found 7"),
            ([header], "<csv>: no samples after the header")):
        try:
            mocap_client.parse_wrist_csv(lines)
            check(False, f"parse_wrist_csv accepted {lines}")
        except ValueError as error:
            check(str(error).startswith(expected), f"parse_wrist_csv: '{error}', expected '{expected}...'")
    (sample,) = mocap_client.parse_wrist_csv([header, "0.5, 0,1,0, 0,1,-2, , 0.25\n"])
    check(sample.time == 0.5 and sample.right.z == -2 and not sample.HasField("left_confidence")
          and sample.right_confidence == 0.25, f"parse_wrist_csv read {sample}")


def config():
    c = rpb.SessionConfig(database=args.database, method=rpb.RECONSTRUCTION_METHOD_FULL,
                          include_diagnostics=True, client_label="python interop test")
    c.fixed_lag.lag_frames = args.lag
    c.overrides.ankle_candidates = args.k1
    c.overrides.pose_neighbours = args.k2
    return c


metadata = (("authorization", f"Bearer {args.key}"),)


def run_stream(client, samples, per_message):
    """One Reconstruct call; returns (started, frames, rejected, summary) as protobuf messages."""
    kinds, frames, rejected, started, summary = [], [], [], None, None
    try:
        for reply in client.reconstruct(config(), samples, samples_per_message=per_message):
            kind = reply.WhichOneof("kind")
            kinds.append(kind)
            if kind == "started":
                started = reply.started
            elif kind == "frames":
                frames.extend(reply.frames.frames)
            elif kind == "rejected":
                rejected.append(reply.rejected)
            elif kind == "summary":
                summary = reply.summary
    except grpc.RpcError as error:
        check(False, f"Reconstruct ended {error.code()}: {error.details()}")
    check(kinds[:1] == ["started"] and kinds.count("started") == 1, f"replies do not start with one `started`: {kinds[:3]}")
    check(kinds[-1:] == ["summary"] and kinds.count("summary") == 1, f"replies do not end with one `summary`: {kinds[-3:]}")
    return started, frames, rejected, summary


def vec(message_or_dict):
    if isinstance(message_or_dict, dict):
        return [float(message_or_dict.get(k, 0.0)) for k in ("x", "y", "z")]
    return [message_or_dict.x, message_or_dict.y, message_or_dict.z]


def quat(message_or_dict):
    if isinstance(message_or_dict, dict):
        return [float(message_or_dict.get(k, 0.0)) for k in ("w", "x", "y", "z")]
    return [message_or_dict.w, message_or_dict.x, message_or_dict.y, message_or_dict.z]


def close(a, b, tolerance=TOLERANCE):
    return len(a) == len(b) and all(abs(x - y) <= tolerance for x, y in zip(a, b))


def compare(label, frames, reference):
    """Python frames (protobuf) against the C++ CLI's JSON frames (dicts). Returns the largest
    difference of root position and rotation components."""
    check(len(frames) == len(reference), f"{label}: {len(frames)} frames, C++ gave {len(reference)}")
    worst = 0.0
    for frame, ref in zip(frames, reference):
        i = frame.index
        where = f"{label} frame {i}"
        check(i == int(ref.get("index", 0)), f"{where}: index vs C++ {ref.get('index')}")
        check(frame.segment == int(ref.get("segment", 0)), f"{where}: segment")
        check(frame.frame_in_segment == int(ref.get("frame_in_segment", 0)), f"{where}: frame_in_segment")
        check(abs(frame.time - float(ref.get("time", 0.0))) <= 1e-9, f"{where}: time {frame.time} vs {ref.get('time')}")
        root, ref_root = vec(frame.root_position), vec(ref["root_position"])
        worst = max([worst] + [abs(x - y) for x, y in zip(root, ref_root)])
        check(close(root, ref_root), f"{where}: root position {root} vs C++ {ref_root}")
        check(len(frame.rotations) == len(ref["rotations"]), f"{where}: {len(frame.rotations)} rotations")
        for j, (q, ref_q) in enumerate(zip(frame.rotations, ref["rotations"])):
            q, ref_q = quat(q), quat(ref_q)
            worst = max([worst] + [abs(x - y) for x, y in zip(q, ref_q)])
            if not check(close(q, ref_q), f"{where} joint {j}: rotation {q} vs C++ {ref_q}"):
                break
        for field in ("pelvis_position", "left_ankle", "right_ankle", "left_wrist", "right_wrist"):
            check(close(vec(getattr(frame, field)), vec(ref[field])), f"{where}: {field}")
        check(close(quat(frame.pelvis_rotation), quat(ref["pelvis_rotation"])), f"{where}: pelvis_rotation")
        if "diagnostics" not in ref:
            check(not frame.HasField("diagnostics"), f"{where}: diagnostics the C++ SDK did not get")
        elif check(frame.HasField("diagnostics"), f"{where}: diagnostics missing"):
            d, ref_d = frame.diagnostics, ref["diagnostics"]
            for field in ("ankle_source_row", "solver_evaluations"):
                check(getattr(d, field) == int(ref_d.get(field, 0)), f"{where}: diagnostics.{field}")
            for field in ("left_foot_planted", "right_foot_planted", "bridged"):
                check(getattr(d, field) == bool(ref_d.get(field, False)), f"{where}: diagnostics.{field}")
            for field in ("wrist_neighbour_distance", "pose_neighbour_distance", "solver_cost", "left_wrist_error"):
                a, b = getattr(d, field), float(ref_d.get(field, 0.0))
                check(math.isclose(a, b, rel_tol=1e-4, abs_tol=1e-6), f"{where}: diagnostics.{field} {a} vs C++ {b}")
        if len(failures) > 20:
            break
    return worst


def compare_example():
    """The example's JSON against the C++ CLI's for the same CSV and config: the same fields (both
    print every field, under the proto's names), skeleton, counts and frames."""
    with open(args.example_json, encoding="utf-8") as stream:
        example = json.load(stream)
    with open(args.example_cxx_json, encoding="utf-8") as stream:
        cxx = json.load(stream)
    check(sorted(example) == sorted(cxx), f"example JSON: top-level fields {sorted(example)} vs C++ {sorted(cxx)}")
    if example.get("frames") and cxx.get("frames"):
        check(sorted(example["frames"][0]) == sorted(cxx["frames"][0]),
              f"example JSON: frame fields {sorted(example['frames'][0])} vs C++ {sorted(cxx['frames'][0])}")
    joints = [joint.get("name") for joint in example.get("started", {}).get("skeleton", {}).get("joints", [])]
    check(joints and joints == [joint.get("name") for joint in cxx["started"]["skeleton"]["joints"]],
          "example JSON: the skeleton's joints differ from the C++ SDK's")
    for field in ("samples", "frames", "rejected_samples", "segments"):
        check(example.get("summary", {}).get(field) == cxx["summary"].get(field), f"example JSON: summary.{field}")
    parsed = json_format.ParseDict(example, rpb.ReconstructTrajectoryResponse())
    worst = compare("example stream_csv.py", list(parsed.frames), cxx["frames"])
    print(f"example stream_csv.py: {len(parsed.frames)} frames, the C++ CLI's JSON fields; largest difference from "
          f"the C++ SDK's frames {worst:.3g}")


def main():
    check_csv_errors()
    with open(args.cxx_json, encoding="utf-8") as stream:
        cxx = json.load(stream)
    reference = cxx["frames"]
    samples = mocap_client.read_wrist_csv(args.csv)
    print(f"{len(samples)} samples from {args.csv}; C++ SDK: {len(reference)} frames, "
          f"session {cxx['started'].get('session_id')}")
    if args.example_json:
        compare_example()

    with mocap_client.Client(args.address, args.key) as client, grpc.insecure_channel(args.address) as bare:
        grpc.channel_ready_future(bare).result(timeout=15)
        sessions = 0
        for per_message in (30, 1):
            label = f"stream, {per_message} sample(s) per message"
            started, frames, rejected, summary = run_stream(client, samples, per_message)
            sessions += 1
            if started is None or summary is None:
                check(False, f"{label}: no started or summary reply")
                continue
            ref_started = cxx["started"]
            check(len(started.skeleton.joints) == len(ref_started["skeleton"]["joints"]), f"{label}: skeleton size")
            check(started.frame_rate == float(ref_started["frame_rate"]), f"{label}: frame_rate")
            check(started.latency_frames == args.lag == int(ref_started["latency_frames"]), f"{label}: latency_frames")
            check(started.config.fixed_lag.lag_frames == args.lag, f"{label}: config echo lacks the lag")
            check(started.config.overrides.ankle_candidates == args.k1, f"{label}: config echo lacks K1")
            check(started.database_frames == int(ref_started["database_frames"]), f"{label}: database_frames")
            check(started.session_id and started.session_id != ref_started.get("session_id"), f"{label}: session id")
            check(not rejected and summary.rejected_samples == 0, f"{label}: samples rejected")
            check(summary.samples == len(samples) and summary.frames == len(frames), f"{label}: summary {summary}")
            worst = compare(label, frames, reference)
            print(f"{label}: {len(frames)} frames, session {started.session_id}; largest difference from the "
                  f"C++ SDK's frames {worst:.3g}")

        unary = client.reconstruct_trajectory(config(), samples, timeout=120)
        worst = compare("ReconstructTrajectory", list(unary.frames), reference)
        print(f"ReconstructTrajectory: {len(unary.frames)} frames; largest difference {worst:.3g}")

        # Errors, as a Python client sees them: without a key on a bare channel, else through the
        # client's stubs (which add the key).
        expect_error("no key", grpc.StatusCode.UNAUTHENTICATED,
                     lambda: rgrpc.ReconstructionStub(bare).Reconstruct(
                         iter([rpb.ReconstructRequest(config=config())]), timeout=30))
        missing = config()
        missing.database = "no-such-database"
        expect_error("unknown database", grpc.StatusCode.NOT_FOUND, lambda: client.reconstruct(missing, []))
        expect_error("samples before config", grpc.StatusCode.INVALID_ARGUMENT,
                     lambda: client.reconstruction.Reconstruct(
                         iter([rpb.ReconstructRequest(samples=rpb.WristSamples(samples=samples[:3]))]), timeout=30))
        expect_error("unknown database (unary)", grpc.StatusCode.NOT_FOUND,
                     lambda: client.reconstruct_trajectory(missing, samples[:3]))

        counters = {}
        for line in client.get_metrics().splitlines():
            if line and not line.startswith("#"):
                name, _, value = line.rpartition(" ")
                counters[name] = float(value)
        total = counters.get("mocap_sessions_total")
        expected = args.sessions_before + sessions
        check(total is not None and total >= expected,
              f"mocap_sessions_total is {total}, expected at least {expected} (the C++, example and Python streams)")
        check(counters.get("mocap_sessions_active", 0) == 0, "mocap_sessions_active is not 0 after the sessions")
        print(f"metrics: mocap_sessions_total {total}, mocap_frames_reconstructed_total "
              f"{counters.get('mocap_frames_reconstructed_total')}")
        databases = [database.name for database in client.list_databases()]
        check(databases == [args.database], f"ListDatabases: {databases}")

        # grpc.health.v1.Health/Check with an empty HealthCheckRequest: SERVING is field 1 = 1.
        health = bare.unary_unary("/grpc.health.v1.Health/Check")(b"", timeout=30)
        check(health == b"\x08\x01", f"health check answered {health!r}, not SERVING (b'\\x08\\x01')")
        listing = reflected_services(bare)
        for service in (b"mocap.v1.MotionStore", b"mocap.v1.Reconstruction", b"mocap.v1.ServerStatus"):
            check(service in listing, f"server reflection does not list {service.decode()}")
        print("health: SERVING; reflection lists MotionStore, Reconstruction, ServerStatus")

    return verdict(f"Python client mocap_client {mocap_client.__version__} agrees with the C++ SDK")


if __name__ == "__main__":
    sys.exit(main())
