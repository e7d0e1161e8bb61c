"""Client: one channel to `mocapd serve`, as the C++ SDK's mocap::client::Client connects.

- The tenant's API key goes with every call as `authorization: Bearer KEY` metadata.
- TLS with `tls=True` (the system's root certificates) or `tls_root_certs=PEM` (trust these).
- Calls safe to repeat (ListDatabases, DescribeDatabase, ListClips, GetMetrics,
  ReconstructTrajectory, FindSimilarPoses) are retried on UNAVAILABLE, up to `max_attempts` in
  all with a doubling backoff from 0.1 s; creates, deletes, imports and live streams are sent once.

The generated stubs on this channel (the key included) are `client.motion_store`,
`client.reconstruction`, `client.pose_search` and `client.server_status`; their messages are in
`mocap_client.v1.*_pb2` (docs/api.md). The methods below are the common cases.
"""
from __future__ import annotations

import collections
import json
import os
from typing import Iterable, Iterator, List, Optional, Sequence, Union

import grpc

from mocap_client.v1 import (motion_store_pb2, motion_store_pb2_grpc, pose_search_pb2_grpc, reconstruction_pb2,
                             reconstruction_pb2_grpc, server_status_pb2, server_status_pb2_grpc)
from mocap_client.wrist_csv import read_wrist_csv

# What the C++ SDK retries on UNAVAILABLE (Retry::kIdempotent in client/src/).
_RETRIED = {
    "mocap.v1.MotionStore": ("ListDatabases", "DescribeDatabase", "ListClips"),
    "mocap.v1.ServerStatus": ("GetMetrics",),
    "mocap.v1.Reconstruction": ("ReconstructTrajectory",),
    "mocap.v1.PoseSearch": ("FindSimilarPoses",),
}


def _service_config(max_attempts: int) -> str:
    retry = {"maxAttempts": max_attempts, "initialBackoff": "0.1s", "maxBackoff": "5s", "backoffMultiplier": 2,
             "retryableStatusCodes": ["UNAVAILABLE"]}
    names = [{"service": service, "method": method} for service, methods in _RETRIED.items() for method in methods]
    return json.dumps({"methodConfig": [{"name": names, "retryPolicy": retry}]})


class _CallDetails(collections.namedtuple("_CallDetails", ("method", "timeout", "metadata", "credentials",
                                                           "wait_for_ready", "compression")),
                   grpc.ClientCallDetails):
    pass


class _ApiKey(grpc.UnaryUnaryClientInterceptor, grpc.UnaryStreamClientInterceptor,
              grpc.StreamUnaryClientInterceptor, grpc.StreamStreamClientInterceptor):
    """Adds `authorization: Bearer KEY` to every call."""

    def __init__(self, key: str):
        self._header = ("authorization", f"Bearer {key}")

    def _with_key(self, details):
        return _CallDetails(details.method, details.timeout, list(details.metadata or ()) + [self._header],
                            details.credentials, getattr(details, "wait_for_ready", None),
                            getattr(details, "compression", None))

    def intercept_unary_unary(self, continuation, details, request):
        return continuation(self._with_key(details), request)

    def intercept_unary_stream(self, continuation, details, request):
        return continuation(self._with_key(details), request)

    def intercept_stream_unary(self, continuation, details, requests):
        return continuation(self._with_key(details), requests)

    def intercept_stream_stream(self, continuation, details, requests):
        return continuation(self._with_key(details), requests)


class Client:
    """A connection to the service. No traffic until the first call; close() (or `with`) ends it.

    address: HOST:PORT. api_key: the tenant's key (`mocapd tenant add-key`; empty: none sent).
    tls / tls_root_certs: TLS trusting the system's roots, or these PEM certificates (bytes or
    str; giving them implies TLS). timeout: seconds for each unary call (retries included).
    """

    def __init__(self, address: str, api_key: str = "", *, tls: bool = False,
                 tls_root_certs: Optional[Union[bytes, str]] = None, timeout: float = 30.0, max_attempts: int = 4,
                 max_receive_message_bytes: int = 4 << 20):
        if not address:
            raise ValueError("no server address")
        options = [("grpc.max_receive_message_length", max_receive_message_bytes)]
        if max_attempts > 1:
            options += [("grpc.enable_retries", 1), ("grpc.service_config", _service_config(max_attempts))]
        if tls or tls_root_certs:
            if isinstance(tls_root_certs, str):
                tls_root_certs = tls_root_certs.encode()
            credentials = grpc.ssl_channel_credentials(root_certificates=tls_root_certs or None)
            self._channel = grpc.secure_channel(address, credentials, options)
        else:
            self._channel = grpc.insecure_channel(address, options)
        self.channel = grpc.intercept_channel(self._channel, _ApiKey(api_key)) if api_key else self._channel
        self.timeout = timeout
        self.motion_store = motion_store_pb2_grpc.MotionStoreStub(self.channel)
        self.reconstruction = reconstruction_pb2_grpc.ReconstructionStub(self.channel)
        self.pose_search = pose_search_pb2_grpc.PoseSearchStub(self.channel)
        self.server_status = server_status_pb2_grpc.ServerStatusStub(self.channel)

    @classmethod
    def from_environment(cls, address: Optional[str] = None, **options) -> "Client":
        """A client for $MOCAP_ADDRESS (default 127.0.0.1:50051) with the key in $MOCAP_API_KEY, as
        the `mocap` CLI reads them."""
        return cls(address or os.environ.get("MOCAP_ADDRESS", "127.0.0.1:50051"),
                   options.pop("api_key", os.environ.get("MOCAP_API_KEY", "")), **options)

    def close(self) -> None:
        self._channel.close()

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # MotionStore and ServerStatus.
    def list_databases(self) -> List[motion_store_pb2.DatabaseSummary]:
        return list(self.motion_store.ListDatabases(motion_store_pb2.ListDatabasesRequest(),
                                                    timeout=self.timeout).databases)

    def get_metrics(self) -> str:
        """The server's counters (Prometheus text)."""
        return self.server_status.GetMetrics(server_status_pb2.GetMetricsRequest(), timeout=self.timeout).text

    # Reconstruction.
    def reconstruct(self, config: reconstruction_pb2.SessionConfig,
                    samples: Iterable[reconstruction_pb2.WristSample], *,
                    samples_per_message: int = 30) -> Iterator[reconstruction_pb2.ReconstructResponse]:
        """A live Reconstruct session: sends the config, the samples (as they come from `samples`,
        which may be a generator fed by a tracker) in messages of `samples_per_message`, then
        finish; yields the server's replies as they arrive: `started` first, then `frames`
        (reply.frames.frames), `rejected` and `input_report` replies, and `summary` last. Raises
        grpc.RpcError if the call fails (e.g. NOT_FOUND for an unknown database). Stopping the
        iteration early cancels the call."""

        def requests():
            yield reconstruction_pb2.ReconstructRequest(config=config)
            batch = []
            for sample in samples:
                batch.append(sample)
                if len(batch) >= max(1, samples_per_message):
                    yield reconstruction_pb2.ReconstructRequest(samples=reconstruction_pb2.WristSamples(samples=batch))
                    batch = []
            if batch:
                yield reconstruction_pb2.ReconstructRequest(samples=reconstruction_pb2.WristSamples(samples=batch))
            yield reconstruction_pb2.ReconstructRequest(finish=reconstruction_pb2.FinishSession())

        call = self.reconstruction.Reconstruct(requests())  # a live session has no deadline
        try:
            yield from call
        finally:
            call.cancel()  # no effect once the call has ended

    def reconstruct_csv(self, config: reconstruction_pb2.SessionConfig, path: Union[str, os.PathLike], *,
                        samples_per_message: int = 30) -> Iterator[reconstruction_pb2.ReconstructResponse]:
        """reconstruct() with the samples of a wrist CSV (mocap_client.wrist_csv, the format of
        `mocap reconstruct --csv`). The file is read and checked before the call starts."""
        return self.reconstruct(config, read_wrist_csv(path), samples_per_message=samples_per_message)

    def reconstruct_trajectory(self, config: reconstruction_pb2.SessionConfig,
                               samples: Sequence[reconstruction_pb2.WristSample],
                               timeout: Optional[float] = None) -> reconstruction_pb2.ReconstructTrajectoryResponse:
        """A whole trajectory in one unary call (retried on UNAVAILABLE)."""
        request = reconstruction_pb2.ReconstructTrajectoryRequest(config=config, samples=samples)
        return self.reconstruction.ReconstructTrajectory(request, timeout=timeout or self.timeout)


def gather(
        replies: Iterable[reconstruction_pb2.ReconstructResponse]) -> reconstruction_pb2.ReconstructTrajectoryResponse:
    """A Reconstruct stream's replies gathered into one message, as `mocap reconstruct` does before
    writing OUTPUT.json: started (its skeleton replaced by a resized one when the stream sends
    one), every frame, refused samples, the input report and the summary."""
    result = reconstruction_pb2.ReconstructTrajectoryResponse()
    for reply in replies:
        kind = reply.WhichOneof("kind")
        if kind == "started":
            result.started.CopyFrom(reply.started)
        elif kind == "frames":
            result.frames.extend(reply.frames.frames)
            if reply.frames.HasField("skeleton"):  # the body sized at the end of the input
                result.started.skeleton.CopyFrom(reply.frames.skeleton)
        elif kind == "rejected":
            result.rejected.append(reply.rejected)
        elif kind == "input_report":
            result.input_report.floor_height = reply.input_report.floor_height
            result.input_report.floor_calibrated = reply.input_report.floor_calibrated
            result.input_report.warnings.extend(reply.input_report.warnings)
        elif kind == "summary":
            result.summary.CopyFrom(reply.summary)
    return result
