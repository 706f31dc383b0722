"""A headless Chromium driven over the DevTools protocol, standard library only.

Chromium talks the protocol over two pipes when started with
--remote-debugging-pipe: it reads commands on its file descriptor 3 and writes
answers and events on 4, one JSON object per message, each ended by a NUL byte.
That is enough to open a page, wait for its scripts, run a line of JavaScript
in it and take a screenshot, without a WebSocket library or an open port.

The browser runs offline: every host name resolves to nothing, so a page that
needs the network shows it (and `requests` lists what it tried to fetch).
"""

from __future__ import annotations

import base64
import json
import os
import select
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path

from raykit import atomic


class BrowserError(Exception):
    pass


def find_chromium() -> str | None:
    return next(filter(None, map(shutil.which, ("chromium", "chromium-browser", "google-chrome"))), None)


class Browser:
    """One headless Chromium with one tab. Use as a context manager."""

    def __init__(self, executable: str, width: int = 1200, height: int = 900,
                 first_answer_timeout: float = 60):
        self.executable = executable
        self.first_answer_timeout = first_answer_timeout
        self.size = (width, height)
        self.requests: list[str] = []          # every URL the page asked for
        self._fresh()

    def _fresh(self) -> None:
        """A new profile and no process: before the first start, and before a start again."""
        self.profile = tempfile.TemporaryDirectory(prefix="raykit-chromium-")
        self.proc: subprocess.Popen | None = None
        self.next_id = 0
        self.buffer = b""
        self.events: list[dict] = []
        self.session: str | None = None

    # --- process -------------------------------------------------------------------

    def __enter__(self) -> "Browser":
        # A Chromium that starts on a loaded machine (a CI runner building in
        # parallel) can take long to answer its first command, and now and then
        # never does. One slow start is waited for; a start that never answers is
        # retried once with a fresh profile before the test is failed.
        self.attempts = 1
        try:
            try:
                self._start(self.first_answer_timeout)
            except BrowserError:
                self.__exit__(None, None, None)
                self._fresh()
                self.attempts = 2
                self._start(self.first_answer_timeout)
        except BaseException:
            self.__exit__(None, None, None)     # no Chromium left behind, whatever stopped the start
            raise
        return self

    def _start(self, first_answer_timeout: float) -> None:
        to_child_r, self.to_child = os.pipe()
        self.from_child, from_child_w = os.pipe()

        def wire_pipes() -> None:          # runs in the child, before exec
            a, b = os.dup(to_child_r), os.dup(from_child_w)
            os.dup2(a, 3)
            os.dup2(b, 4)

        args = [
            self.executable, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
            "--no-first-run", "--no-default-browser-check", "--disable-background-networking",
            "--disable-component-update", "--disable-sync", "--disable-extensions",
            "--disable-default-apps", "--mute-audio", "--hide-scrollbars",
            # Offline: no name resolves, so nothing on the network can load.
            "--host-resolver-rules=MAP * ~NOTFOUND",
            f"--user-data-dir={self.profile.name}", f"--window-size={self.size[0]},{self.size[1]}",
            "--remote-debugging-pipe", "about:blank",
        ]
        self.proc = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL, pass_fds=(3, 4),
                                     preexec_fn=wire_pipes, start_new_session=True)
        os.close(to_child_r)
        os.close(from_child_w)
        targets = self.call("Target.getTargets", timeout=first_answer_timeout)["targetInfos"]
        page = next((t for t in targets if t["type"] == "page"), None)
        target = page["targetId"] if page else self.call("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.call("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        self.call("Page.enable", session=True)
        self.call("Network.enable", session=True)
        self.call("Emulation.setDeviceMetricsOverride", session=True, width=self.size[0],
                  height=self.size[1], deviceScaleFactor=1, mobile=False)

    def __exit__(self, *exc) -> None:
        if self.proc is not None and self.proc.poll() is None:
            try:
                self.send("Browser.close")
                self.proc.wait(timeout=5)
            except (OSError, subprocess.TimeoutExpired, BrowserError):
                # Chromium's helpers share its process group (start_new_session): end them too.
                try:
                    os.killpg(self.proc.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                self.proc.wait()
        for fd in (self.to_child, self.from_child):
            try:
                os.close(fd)
            except OSError:
                pass
        self.profile.cleanup()

    # --- protocol ------------------------------------------------------------------

    def send(self, method: str, session: bool = False, **params) -> int:
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params}
        if session:
            message["sessionId"] = self.session
        data = json.dumps(message).encode() + b"\0"
        try:
            os.write(self.to_child, data)
        except BrokenPipeError:
            raise BrowserError("Chromium has exited") from None
        return self.next_id

    def _read(self, deadline: float) -> dict | None:
        while b"\0" not in self.buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            ready, _, _ = select.select([self.from_child], [], [], min(left, 0.5))
            if ready:
                chunk = os.read(self.from_child, 1 << 16)
                if not chunk:
                    raise BrowserError("Chromium closed the DevTools pipe")
                self.buffer += chunk
        raw, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(raw)

    def _dispatch(self, message: dict) -> None:
        if message.get("method") == "Network.requestWillBeSent":
            self.requests.append(message["params"]["request"]["url"])
        self.events.append(message)

    def call(self, method: str, session: bool = False, timeout: float = 30, **params) -> dict:
        wanted = self.send(method, session, **params)
        deadline = time.monotonic() + timeout
        while True:
            message = self._read(deadline)
            if message is None:
                raise BrowserError(f"Chromium did not answer {method} within {timeout:g} s")
            if message.get("id") == wanted:
                if "error" in message:
                    raise BrowserError(f"{method}: {message['error'].get('message')}")
                return message.get("result", {})
            self._dispatch(message)

    def wait_event(self, method: str, timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        for i, e in enumerate(self.events):
            if e.get("method") == method:
                del self.events[: i + 1]
                return True
        self.events.clear()
        while True:
            message = self._read(deadline)
            if message is None:
                return False
            self._dispatch(message)
            if message.get("method") == method:
                self.events.clear()
                return True

    # --- what a test does ----------------------------------------------------------

    def open(self, url: str, timeout: float = 20) -> None:
        """Loads `url` and waits for its load event."""
        self.events.clear()
        self.requests.clear()
        result = self.call("Page.navigate", session=True, url=url)
        if result.get("errorText"):
            raise BrowserError(f"{url}: {result['errorText']}")
        if not self.wait_event("Page.loadEventFired", timeout):
            raise BrowserError(f"{url} did not finish loading within {timeout:g} s")

    def evaluate(self, expression: str, timeout: float = 20):
        """The value of a JavaScript expression in the page; promises are awaited."""
        result = self.call("Runtime.evaluate", session=True, timeout=timeout, expression=expression,
                           awaitPromise=True, returnByValue=True)
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text")
            raise BrowserError(f"the page's script failed: {text}")
        return result["result"].get("value")

    def screenshot(self, path: Path, whole_page: bool = True) -> None:
        """A PNG of the whole page (or only the window) at `path`."""
        if not whole_page:
            self._write_png(path, self.call("Page.captureScreenshot", session=True, format="png")["data"])
            return
        width, height = self.evaluate(
            "[document.documentElement.scrollWidth, Math.max(document.documentElement.scrollHeight,"
            " ...Array.from(document.querySelectorAll('#doc-content'), e => e.scrollHeight))]")
        width, height = max(width, self.size[0]), min(max(height, self.size[1]), 8000)
        self.call("Emulation.setDeviceMetricsOverride", session=True, width=width, height=height,
                  deviceScaleFactor=1, mobile=False)
        data = self.call("Page.captureScreenshot", session=True, format="png")["data"]
        self.call("Emulation.setDeviceMetricsOverride", session=True, width=self.size[0],
                  height=self.size[1], deviceScaleFactor=1, mobile=False)
        self._write_png(path, data)

    @staticmethod
    def _write_png(path: Path, data: str) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic.write(path, base64.b64decode(data))
