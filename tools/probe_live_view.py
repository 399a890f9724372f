#!/usr/bin/env python3
"""Probes a live view (`trephine run --realtime --view`) as hostile clients do,
and prints what held as JSON.

It runs SCENE in real time under a lowered descriptor limit (`ulimit -n`),
then, while it goes:
  - opens the WebSocket from another site's page (Origin) and under a rebound
    name (Host), and asks for the page under that name: each ATTEMPTS times,
    noting the answers and how many bytes the first one got in 2 s;
  - opens the WebSocket as the server's own page (it must be answered);
  - holds IDLE connections that send nothing, notes how many are still open
    after 1 s and after 7 s, and whether a page is served meanwhile, after
    7 s and once they are closed;
and at the end reads the exporter's counters (files written, failed, the
server's refusals and timeouts) from summary.json.

  tools/probe_live_view.py [--trephine build/bin/trephine] [--scene scenes/integrated.xml]
                           [--duration 20] [--nofile 128] [--idle 150] [--attempts 10] --out DIR
"""
import argparse
import json
import os
import re
import socket
import subprocess
import sys
import time

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--trephine", default="build/bin/trephine")
parser.add_argument("--scene", default="scenes/integrated.xml")
parser.add_argument("--duration", default="20", help="seconds of the run (real time)")
parser.add_argument("--nofile", type=int, default=128, help="the run's descriptor limit (ulimit -n)")
parser.add_argument("--idle", type=int, default=150, help="idle connections held")
parser.add_argument("--attempts", type=int, default=10, help="attempts of each foreign request")
parser.add_argument("--out", required=True, help="the run's output directory")
options = parser.parse_args()

command = (f"ulimit -n {options.nofile}; exec {options.trephine} run {options.scene} --realtime --view 0 "
           f"--duration {options.duration} --out {options.out} --quiet")
run = subprocess.Popen(["bash", "-c", command], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
port = None
printed = []
while port is None:
    line = run.stdout.readline()
    if not line:
        sys.exit("the run ended before serving:\n" + "".join(printed))
    printed.append(line)
    found = re.search(r"view\s+http://127\.0\.0\.1:(\d+)/", line)
    if found:
        port = int(found.group(1))


def upgrade(host, origin=None):
    origin_line = f"Origin: {origin}\r\n" if origin else ""
    return (f"GET /stream HTTP/1.1\r\nHost: {host}\r\n{origin_line}Upgrade: websocket\r\nConnection: Upgrade\r\n"
            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n").encode()


def page(host):
    return f"GET / HTTP/1.1\r\nHost: {host}\r\n\r\n".encode()


def ask(request, seconds):
    """Sends `request` on a new connection and reads for `seconds`: the status line and the bytes read."""
    try:
        connection = socket.create_connection(("127.0.0.1", port), timeout=3)
        connection.sendall(request)
    except OSError as error:
        return f"no connection: {error}", 0
    answer = b""
    end = time.time() + seconds
    connection.settimeout(0.2)
    while time.time() < end:
        try:
            data = connection.recv(1 << 20)
            if not data:
                break
            answer += data
        except socket.timeout:
            pass
        except OSError:
            break
    connection.close()
    return answer.split(b"\r\n", 1)[0].decode(errors="replace"), len(answer)


def still_open(connection):
    connection.setblocking(False)
    try:
        return connection.recv(1) != b""
    except BlockingIOError:
        return True
    except OSError:
        return False


loopback = f"127.0.0.1:{port}"
rebound = f"evil.example:{port}"
result = {"port": port}
for name, request in [("foreign_origin_upgrade", upgrade(loopback, "http://evil.example")),
                      ("foreign_host_upgrade", upgrade(rebound)),
                      ("foreign_host_page", page(rebound))]:
    answers = [ask(request, 2.0 if i == 0 else 0.3) for i in range(options.attempts)]
    result[name] = {"attempts": options.attempts,
                    "answers": {status: sum(1 for s, _ in answers if s == status) for status, _ in answers},
                    "bytes_to_the_first_in_2_s": answers[0][1]}
result["own_page_upgrade"] = ask(upgrade(f"localhost:{port}", f"http://localhost:{port}"), 0.5)[0]

idle = []
for _ in range(options.idle):
    try:
        idle.append(socket.create_connection(("127.0.0.1", port), timeout=3))
    except OSError as error:
        result["idle_not_connected"] = str(error)
        break
time.sleep(1.0)
result["idle_open_after_1_s"] = sum(still_open(c) for c in idle)
result["page_while_idle_held"] = ask(page(loopback), 1.0)[0]
time.sleep(6.0)
result["idle_open_after_7_s"] = sum(still_open(c) for c in idle)
result["page_after_7_s"] = ask(page(loopback), 2.0)[0]
for connection in idle:
    connection.close()
time.sleep(0.5)
result["page_after_idle_closed"] = ask(page(loopback), 2.0)[0]

rest = run.communicate(timeout=300)[0]
result["exit_code"] = run.returncode
try:
    with open(os.path.join(options.out, "summary.json")) as file:
        summary = json.load(file)
    result["complete"] = summary.get("complete")
    result["output_errors"] = summary.get("output_errors", [])
    for component in summary["components"].values():
        if component.get("type") == "VtkExporter":
            result["exporter_counters"] = component.get("counters")
except (OSError, ValueError) as error:
    result["summary"] = f"not read: {error}"
result["run_said"] = ("".join(printed) + rest)[-800:]
print(json.dumps(result, indent=1))
