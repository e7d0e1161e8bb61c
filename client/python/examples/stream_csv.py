#!/usr/bin/env python3
"""Streams a wrist CSV to `mocapd serve` and writes the whole-body frames it answers with.

    MOCAP_API_KEY=mk_... python3 stream_csv.py --database walks --csv wrists.csv -o walk.json

The CSV is the one `mocap reconstruct --csv` reads (time,left_x,left_y,left_z,right_x,right_y,
right_z, ...; metres, Y up). The session reconstructs at a fixed lag of --lag frames, as a live
tracker's stream would be; each frame is printed as it arrives. The output is the JSON document
`mocap reconstruct -o NAME` writes as NAME.json (the skeleton, every frame, refused samples, the
summary, under the same field names), so whatever reads that file reads this one too.
"""
import argparse
import os
import sys

import grpc
from google.protobuf import json_format

import mocap_client
from mocap_client.v1 import reconstruction_pb2


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--address", default=os.environ.get("MOCAP_ADDRESS", "127.0.0.1:50051"))
    parser.add_argument("--key", default=os.environ.get("MOCAP_API_KEY", ""), help="default: $MOCAP_API_KEY")
    parser.add_argument("--tls", action="store_true", help="TLS, trusting the system's root certificates")
    parser.add_argument("--tls-root-certs", metavar="PEM", help="TLS, trusting these certificates")
    parser.add_argument("--database", required=True)
    parser.add_argument("--csv", required=True, help="wrist samples (the CSV of mocap reconstruct --csv)")
    parser.add_argument("--lag", type=int, default=5, help="frames each answer waits for (default 5)")
    parser.add_argument("-o", "--output", default="reconstruction.json")
    args = parser.parse_args()

    config = reconstruction_pb2.SessionConfig(
        database=args.database, method=reconstruction_pb2.RECONSTRUCTION_METHOD_FULL,
        estimate_performer_height=True,  # learn the body's size from the wrists' reach as they come
        client_label="stream_csv.py")
    config.fixed_lag.lag_frames = args.lag

    replies = []
    try:
        root_certs = open(args.tls_root_certs, "rb").read() if args.tls_root_certs else None
        with mocap_client.Client(args.address, args.key, tls=args.tls, tls_root_certs=root_certs) as client:
            for reply in client.reconstruct_csv(config, args.csv):  # replies as the server sends them
                replies.append(reply)
                kind = reply.WhichOneof("kind")
                if kind == "started":
                    print(f"session {reply.started.session_id}: {len(reply.started.skeleton.joints)} joints, "
                          f"{reply.started.frame_rate:g} fps, {reply.started.latency_frames} frames behind")
                for frame in reply.frames.frames:
                    p = frame.pelvis_position
                    print(f"frame {frame.index:5d}  t {frame.time:7.3f} s  pelvis {p.x:6.3f} {p.y:6.3f} {p.z:6.3f}")
                if kind == "rejected":
                    print(f"sample {reply.rejected.sample_index} refused: {reply.rejected.reason}", file=sys.stderr)
    except (OSError, ValueError) as error:  # the CSV or the certificates
        sys.exit(f"stream_csv.py: {error}")
    except grpc.RpcError as error:  # the call: UNAUTHENTICATED, NOT_FOUND, UNAVAILABLE, ...
        sys.exit(f"stream_csv.py: {error.code().name}: {error.details()}")

    result = mocap_client.gather(replies)
    with open(args.output, "w", encoding="utf-8") as out:
        out.write(json_format.MessageToJson(result, preserving_proto_field_name=True,
                                            including_default_value_fields=True))
    print(f"{result.summary.frames} frames from {result.summary.samples} samples; wrote {args.output}")


if __name__ == "__main__":
    main()
