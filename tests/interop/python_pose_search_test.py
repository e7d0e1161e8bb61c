#!/usr/bin/env python3
"""The PoseSearch service from Python's grpcio, checked against the C++ SDK (`mocap similar`).

  python_pose_search_test.py --address HOST:PORT --key KEY --database NAME \
      --query CLIP.bvh --frames A:B --step N --top K --cxx-json CXX.json

Run with a Python that has mocap_client installed (its generated stubs, on a bare grpcio channel).
CXX.json is what `mocap similar --database NAME --query CLIP.bvh --frames A:B --step N --top K
--json` printed. Checks:
  - FindSimilarPoses from Python (the BVH text, the same frames, top K) answers the same query
    frames with the same matches as the C++ SDK: database, clip id, file, frame, database frame,
    and distances, per-group distances and alignment within 1e-5;
  - StreamSimilarPoses gives the same results in parts, in query-frame order;
  - the default scaling sent explicitly (BODY_SCALING_BONE_DIRECTIONS) gives the same matches;
  - errors map to the documented codes: UNAUTHENTICATED without a key, NOT_FOUND for a database
    that is not there, INVALID_ARGUMENT naming top_k when it is over the limit or naming scaling
    for an enum value the server does not know;
  - server reflection lists mocap.v1.PoseSearch.
"""
import argparse
import json
import math
import sys

TOLERANCE = 1e-5
GROUPS = ("spine", "head", "left_arm", "right_arm", "left_leg", "right_leg")


def parse_args():
    parser = argparse.ArgumentParser()
    for name in ("--address", "--key", "--database", "--query", "--frames", "--cxx-json"):
        parser.add_argument(name, required=True)
    parser.add_argument("--step", type=int, required=True)
    parser.add_argument("--top", type=int, required=True)
    return parser.parse_args()


args = parse_args()

import grpc  # noqa: E402
from mocap_client.v1 import pose_search_pb2 as ppb  # noqa: E402
from mocap_client.v1 import pose_search_pb2_grpc as pgrpc  # noqa: E402
from interop_checks import check, expect_error, failures, reflected_services, verdict  # noqa: E402

metadata = (("authorization", f"Bearer {args.key}"),)


def request(database=None, top=None, scaling=None):
    first, last = (int(x) for x in args.frames.split(":"))
    with open(args.query, "rb") as stream:
        bvh = ppb.BvhQuery(bvh=stream.read(), file_name="query.bvh", first_frame=first, last_frame=last,
                           frame_step=args.step)
    out = ppb.FindSimilarPosesRequest(databases=[database or args.database], bvh=bvh, top_k=top or args.top)
    if scaling is not None:
        out.scaling = scaling
    return out


def close(a, b):
    return math.isclose(float(a), float(b), rel_tol=TOLERANCE, abs_tol=TOLERANCE)


def compare(label, results, reference):
    check(len(results) == len(reference), f"{label}: {len(results)} query frames, C++ gave {len(reference)}")
    for result, ref in zip(results, reference):
        where = f"{label} query frame {result.query_frame}"
        check(result.query_frame == ref["query_frame"], f"{where}: C++ has query frame {ref['query_frame']}")
        check(len(result.matches) == len(ref["matches"]), f"{where}: {len(result.matches)} matches")
        for rank, (match, ref_match) in enumerate(zip(result.matches, ref["matches"])):
            at = f"{where} match {rank}"
            check((match.database, match.clip_id, match.file_name, match.frame, match.database_frame) ==
                  (ref_match["database"], ref_match["clip_id"], ref_match["file"], ref_match["frame"],
                   ref_match["database_frame"]), f"{at}: {match.file_name} frame {match.frame} vs C++ "
                                                 f"{ref_match['file']} frame {ref_match['frame']}")
            check(close(match.distance, ref_match["distance"]), f"{at}: distance {match.distance}")
            for group in GROUPS:
                check(close(getattr(match.group_distances, group), ref_match["group_distances"][group]),
                      f"{at}: {group} distance")
            for field in ("yaw_degrees", "x_body_scales", "z_body_scales"):
                check(close(getattr(match.alignment, field), ref_match["alignment"][field]), f"{at}: alignment {field}")
        if len(failures) > 20:
            break


def main():
    with open(args.cxx_json, encoding="utf-8") as stream:
        reference = json.load(stream)["results"]
    with grpc.insecure_channel(args.address) as channel:
        grpc.channel_ready_future(channel).result(timeout=15)
        stub = pgrpc.PoseSearchStub(channel)

        unary = stub.FindSimilarPoses(request(), metadata=metadata, timeout=300)
        compare("FindSimilarPoses", list(unary.results), reference)
        print(f"FindSimilarPoses: {len(unary.results)} query frames, top {args.top}; same matches as the C++ SDK")

        explicit = stub.FindSimilarPoses(request(scaling=ppb.BODY_SCALING_BONE_DIRECTIONS), metadata=metadata,
                                         timeout=300)
        compare("FindSimilarPoses with scaling BODY_SCALING_BONE_DIRECTIONS (the default)", list(explicit.results),
                reference)

        parts = list(stub.StreamSimilarPoses(request(), metadata=metadata, timeout=300))
        streamed = [result for part in parts for result in part.results]
        compare("StreamSimilarPoses", streamed, reference)
        print(f"StreamSimilarPoses: {len(parts)} parts, {len(streamed)} query frames; same matches")

        expect_error("no key", grpc.StatusCode.UNAUTHENTICATED, lambda: stub.FindSimilarPoses(request(), timeout=30))
        expect_error("unknown database", grpc.StatusCode.NOT_FOUND,
                     lambda: stub.FindSimilarPoses(request(database="no-such-database"), metadata=metadata, timeout=30))
        expect_error("top_k over the limit", grpc.StatusCode.INVALID_ARGUMENT,
                     lambda: stub.StreamSimilarPoses(request(top=1000), metadata=metadata, timeout=30), named="top_k")
        expect_error("a scaling this server does not know", grpc.StatusCode.INVALID_ARGUMENT,
                     lambda: stub.FindSimilarPoses(request(scaling=9), metadata=metadata, timeout=30), named="scaling")

        check(b"mocap.v1.PoseSearch" in reflected_services(channel), "server reflection does not list mocap.v1.PoseSearch")

    return verdict("Python grpcio PoseSearch client agrees with the C++ SDK")


if __name__ == "__main__":
    sys.exit(main())
