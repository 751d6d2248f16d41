"""Sun studies and batches on a real Ray cluster of two nodes, each a raylet with one CPU and an
object store of its own, both on 127.0.0.1 only, started by Ray's own multi-node harness
(`ray.cluster_utils.Cluster`) and stopped at the end.

Why not `ray start`: for a second node, `ray start` turns the address 127.0.0.1 into the
machine's own network address (`services.resolve_ip_for_localhost`) and binds its servers
there; with loopback addresses it refuses a second node. The harness starts the same processes
(GCS, raylets, object stores, workers) with the address given."""

import os

# Keep every node's address the loopback one (Ray otherwise takes the machine's own address
# for a node): set before Ray is imported.
os.environ["RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"] = "0"
os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")

import json  # noqa: E402
import threading  # noqa: E402

import numpy as np  # noqa: E402
import pytest  # noqa: E402

import penumbra as pb  # noqa: E402
from penumbra import batch, study  # noqa: E402
from conftest import FIXTURES  # noqa: E402

import ray  # noqa: E402
from ray.cluster_utils import Cluster  # noqa: E402


def listening():
    """The TCP addresses (address, port) listening on this machine, from /proc."""
    out = set()
    for name, width in (("/proc/net/tcp", 8), ("/proc/net/tcp6", 32)):
        try:
            lines = open(name).read().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            fields = line.split()
            if fields[3] != "0A":  # LISTEN
                continue
            addr, port = fields[1].split(":")
            if width == 8:
                ip = ".".join(str(int(addr[i:i + 2], 16)) for i in (6, 4, 2, 0))
            else:
                words = [addr[i:i + 8] for i in range(0, 32, 8)]
                if words[:2] == ["00000000"] * 2 and words[2] == "FFFF0000":
                    w = words[3]
                    ip = ".".join(str(int(w[i:i + 2], 16)) for i in (6, 4, 2, 0))
                elif addr == "0" * 24 + "01000000":
                    ip = "::1"
                else:
                    ip = "::" if addr == "0" * 32 else addr
            out.add((ip, int(port, 16)))
    return out


def warm_up(c):
    """Starts a worker process on each node (a second or so each), so that a test's first
    tasks are not all taken by the node whose worker was up first."""
    ray.init(address=c.address)
    try:
        @ray.remote(num_cpus=1, scheduling_strategy="SPREAD")
        def node():
            import time

            time.sleep(0.5)
            return ray.get_runtime_context().get_node_id()

        for _ in range(10):
            if len(set(ray.get([node.remote() for _ in range(4)]))) == 2:
                break
        else:
            raise AssertionError("the cluster's two nodes did not both take tasks")
    finally:
        ray.shutdown()


@pytest.fixture(scope="module")
def cluster():
    before = listening()
    c = Cluster(initialize_head=True, head_node_args={
        "num_cpus": 1, "node_ip_address": "127.0.0.1", "include_dashboard": False})
    worker = c.add_node(num_cpus=1, node_ip_address="127.0.0.1")
    c.wait_for_nodes()
    warm_up(c)
    try:
        yield c, worker, before
    finally:
        if ray.is_initialized():
            ray.shutdown()
        c.shutdown()
    # Stopped: none of the cluster's servers is left.
    import time

    import psutil

    def left():
        return [p.info["name"] for p in psutil.process_iter(["name"])
                if p.info["name"] in ("raylet", "gcs_server")]

    for _ in range(100):
        if not left():
            break
        time.sleep(0.1)
    assert not left(), f"the cluster left {left()} running"


def test_the_cluster_listens_on_loopback_only(cluster):
    c, _, before = cluster
    opened = listening() - before
    assert opened, "the cluster opened no port"
    assert all(ip in ("127.0.0.1", "::1") for ip, _ in opened), sorted(opened)


def test_a_day_on_two_nodes_is_the_same_bits_as_one_process(cluster):
    c, _, _ = cluster
    scene = pb.Scene.load(FIXTURES / "sun.toml").with_size(48, 36)
    args = (scene, 48.85, 2.35, "2026-06-21", "2026-06-22")
    kw = dict(timezone="Europe/Paris", samples=16, chunk_steps=2)
    here = study.sun_hours(*args, **kw)
    seen = []
    there = study.sun_hours(*args, engine="ray", address=c.address, progress=seen.append, **kw)
    assert np.array_equal(here, there)
    assert seen[-1]["done"] == seen[-1]["total"] == 16
    # The runs went to both nodes.
    assert len({s["node"] for s in seen}) == 2, seen
    assert all(s["peak_mb"] > 0 for s in seen)
    assert not ray.is_initialized()  # joined for the study, left after it


def test_a_node_stopped_mid_study_leaves_every_step_counted_once(cluster):
    c, worker, _ = cluster
    # A sensor in the open, facing up, sees the whole sun at every step between 9:00 and
    # 15:00 in June: weighted 2^k, each step is one bit of the sum, which shows a step lost
    # or counted twice. The camera's pixels make each run take a while.
    scene = pb.Scene.load(FIXTURES / "sun.toml").with_size(96, 72)
    start, end = "2026-06-21 09:00", "2026-06-21 15:00"
    steps = study.sun_steps(48.85, 2.35, start, end, 10, "Europe/Paris")
    n = len(steps.hours)
    assert n == 36 and steps.elevation_deg.min() > 20
    weights = 6.0 * 2.0 ** np.arange(n)  # 6 x 10 minutes = 1 hour: V x 2^k
    kw = dict(timezone="Europe/Paris", step_minutes=10, weights=weights, chunk_steps=1,
              samples=256, points=[[9.0, 0.0, 9.0]], normals=[0.0, 1.0, 0.0])
    stopped = threading.Event()

    def stop_the_worker_node(report):
        if report["done"] >= 4 and not stopped.is_set():
            stopped.set()
            c.remove_node(worker, allow_graceful=False)

    got = study.sun_hours(scene, 48.85, 2.35, start, end, engine="ray", address=c.address,
                          progress=stop_the_worker_node, **kw)
    assert stopped.is_set()
    assert got[0] == float(2.0 ** n - 1), got  # every bit once
    assert np.array_equal(got, study.sun_hours(scene, 48.85, 2.35, start, end, **kw))
    # The node comes back for the tests after this one.
    c.add_node(num_cpus=1, node_ip_address="127.0.0.1")
    c.wait_for_nodes()
    warm_up(c)


def test_a_batch_on_the_cluster(cluster, tmp_path):
    c, _, _ = cluster
    small = pb.Scene.load(FIXTURES / "spot.toml").with_size(32, 24)
    jobs = [{"scene": small, "technique": "depth-complexity", "samples": 16, "backend": "cpu",
             "name": f"spot-{k}"} for k in range(6)]
    jobs.append({"scene": small, "technique": "no-such-technique", "name": "bad"})
    records = batch.run(jobs, tmp_path, engine="ray", address=c.address)
    assert [r["status"] for r in records] == ["done"] * 6 + ["failed"]
    assert "no-such-technique" in records[-1]["error"]
    assert len({r["node"] for r in records[:6]}) == 2, records
    want = small.render("depth-complexity", samples=16, backend="cpu")
    for k in range(6):
        assert np.array_equal(pb.read_exr(tmp_path / f"spot-{k}.exr")["V"], want)
    manifest = [json.loads(x) for x in (tmp_path / batch.MANIFEST).read_text().splitlines()]
    assert sorted(m["name"] for m in manifest) == sorted(r["name"] for r in records)
    again = batch.run(jobs, tmp_path, engine="ray", address=c.address)
    assert [r["status"] for r in again] == ["skipped"] * 6 + ["failed"]


def test_a_day_over_six_real_meshes_on_two_nodes_and_against_the_reference(cluster):
    # The scale scene: six public meshes, 209,388 triangles, in the sun of a June day in
    # Madrid, hourly. The same bits on two nodes as in one process; depth-complexity's hours
    # within 0.05 h of the reference's at the same 64 samples.
    c, _, _ = cluster
    scene = pb.Scene.load(FIXTURES.parent / "scale" / "scale.toml").with_size(48, 36)
    assert scene.triangle_count > 200_000
    args = (scene, 40.42, -3.70, "2026-06-21", "2026-06-22")
    kw = dict(timezone="Europe/Madrid", samples=64, chunk_steps=4)
    here = study.sun_hours(*args, **kw)
    there = study.sun_hours(*args, engine="ray", address=c.address, **kw)
    assert np.array_equal(here, there)
    rays = study.sun_hours(*args, technique="reference", **kw)
    diff = np.abs(here - rays)
    assert here.max() > 14 and here.min() < 8  # sun and shade
    assert diff.mean() <= 0.01, diff.mean()
    assert np.percentile(diff, 99) <= 0.05, np.percentile(diff, 99)
    print(f"scale scene, a day: |dc - reference| mean {diff.mean():.4f} h, "
          f"99th percentile {np.percentile(diff, 99):.4f} h, max {diff.max():.4f} h")
