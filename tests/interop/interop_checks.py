"""What the Python interop tests share: mismatch bookkeeping, expected gRPC errors, reflection."""
import sys

import grpc

failures = []


def check(condition, message):
    """Records a mismatch (printed at once) unless `condition` holds; returns `condition`."""
    if not condition:
        failures.append(message)
        print(f"  MISMATCH: {message}", file=sys.stderr)
    return condition


def expect_error(what, code, call, named=None):
    """`call()` (unary, or a stream read to its end) must fail with `code`, its message naming `named`."""
    try:
        result = call()
        if hasattr(result, "__iter__"):
            for _ in result:
                pass
        check(False, f"{what}: succeeded, expected {code.name}")
    except grpc.RpcError as error:
        check(error.code() == code, f"{what}: {error.code()} ({error.details()}), expected {code.name}")
        if named:
            check(named in error.details(), f"{what}: the message '{error.details()}' does not name {named}")


def reflected_services(channel):
    """The raw answer of grpc.reflection.v1alpha.ServerReflection to list_services (field 7, an
    empty string), as a generic tool such as grpcurl would ask."""
    return b"".join(channel.stream_stream("/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo")(
        iter([b"\x3a\x00"]), timeout=30))


def verdict(what):
    """Prints the outcome; the exit code."""
    if failures:
        print(f"FAIL: {len(failures)} mismatches; first: {failures[0]}", file=sys.stderr)
        return 1
    print(f"PASS: {what}")
    return 0
