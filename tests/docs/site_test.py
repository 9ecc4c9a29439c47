"""The documentation site (build/docs/html) as a reader meets it, in headless Chromium.

The site is served on 127.0.0.1 by this process (every request and its status is logged), and
Chromium is driven over the DevTools protocol. The index and one page of each kind (a Markdown
guide, the Python, C++ and C API, the command's reference) must load with every resource found
(no status of 400 or more in the server's log or the browser's, no failed request), no console
error or uncaught exception, the theme's stylesheet applied and the page's own content shown.
The search, which runs in JavaScript, must find NeighborList as a Python class and a C++ class.
A crawler then resolves every internal link and fragment of every page of the site. The
index is also saved as a screenshot, build/docs/index.png.

Environment: TRICELL_DOCS_HTML (the site), TRICELL_CHROMIUM (default /usr/bin/chromium).
"""
import functools
import html.parser
import http.server
import json
import os
import posixpath
import subprocess
import tempfile
import threading
import time
import urllib.parse

import pytest

HTML = os.environ.get("TRICELL_DOCS_HTML", "")
CHROMIUM = os.environ.get("TRICELL_CHROMIUM", "/usr/bin/chromium")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--remote-debugging-port=0"]

# A page of each kind, and what must be on it once loaded (a JavaScript expression).
PAGES = {
    "docs/index.html": "document.body.innerText.includes('A taste of each interface')",
    "docs/cpp.html": "document.getElementById('verlet-lists') !== null",
    "docs/api/python.html": "document.getElementById('tricell.NeighborList') !== null",
    "docs/api/cpp.html": "document.body.innerText.includes('compute_neighbors')",
    "docs/api/c.html": "document.body.innerText.includes('tricell_neighbors')",
    "docs/api/cli.html": "document.body.innerText.includes('usage: tricell neighbors')",
}
# The theme's stylesheet is applied: its navigation column is fixed at the left.
STYLED = "getComputedStyle(document.querySelector('.wy-nav-side')).position === 'fixed'"


class LoggingHandler(http.server.SimpleHTTPRequestHandler):
    log = None  # (path, status) of every request, set by the server below

    def log_request(self, code="-", size="-"):
        self.log.append((self.path, int(code)))

    def log_message(self, *args):
        pass


@pytest.fixture(scope="module")
def server():
    if not os.path.isfile(os.path.join(HTML, "docs", "index.html")):
        pytest.fail("no site in TRICELL_DOCS_HTML=%r: build the docs target first" % HTML)
    log = []
    handler = type("Handler", (LoggingHandler,), {"log": log})
    httpd = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(handler, directory=HTML))
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield "http://127.0.0.1:%d/" % httpd.server_address[1], log
    httpd.shutdown()
    httpd.server_close()


class Chromium:
    """Headless Chromium with one tab, driven over the DevTools protocol."""

    def __init__(self, profile):
        import websocket  # Debian: python3-websocket

        self.stderr = open(os.path.join(profile, "stderr"), "w")
        self.process = subprocess.Popen([CHROMIUM, *FLAGS, "--user-data-dir=" + profile,
                                         "about:blank"], stdout=subprocess.DEVNULL,
                                        stderr=self.stderr)
        port_file = os.path.join(profile, "DevToolsActivePort")
        deadline = time.time() + 60
        while not (os.path.exists(port_file) and len(open(port_file).read().split()) == 2):
            if self.process.poll() is not None or time.time() > deadline:
                raise RuntimeError("%s did not start its DevTools server" % CHROMIUM)
            time.sleep(0.1)
        port, path = open(port_file).read().split()
        self.socket = websocket.create_connection("ws://127.0.0.1:%s%s" % (port, path),
                                                  timeout=60, suppress_origin=True)
        self.next_id = 0
        self.events = []
        target = self.call("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.call("Target.attachToTarget", targetId=target,
                                 flatten=True)["sessionId"]
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.call(domain + ".enable", session=self.session)

    def call(self, method, session=None, **params):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params}
        if session:
            message["sessionId"] = session
        self.socket.send(json.dumps(message))
        while True:
            reply = json.loads(self.socket.recv())
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError("%s: %s" % (method, reply["error"]))
                return reply["result"]
            self.events.append(reply)

    def tab(self, method, **params):
        return self.call(method, session=self.session, **params)

    def evaluate(self, expression):
        result = self.tab("Runtime.evaluate", expression=expression, returnByValue=True)
        if "exceptionDetails" in result:
            raise RuntimeError("%s: %s" % (expression, result["exceptionDetails"]))
        return result["result"].get("value")

    def pump(self, seconds):
        """Reads events for about `seconds`."""
        self.socket.settimeout(seconds)
        try:
            while True:
                self.events.append(json.loads(self.socket.recv()))
        except Exception:  # noqa: BLE001 - the timeout that ends the wait
            pass
        finally:
            self.socket.settimeout(60)

    def load(self, url):
        """Navigates, waits for the load event and then for the network to be idle for half a
        second; returns the events of the load."""
        self.events = []
        self.tab("Page.navigate", url=url)
        deadline = time.time() + 60
        while time.time() < deadline:
            before = len(self.events)
            self.pump(0.5)
            loaded = any(e.get("method") == "Page.loadEventFired" for e in self.events)
            started = {e["params"]["requestId"] for e in self.events
                       if e.get("method") == "Network.requestWillBeSent"}
            ended = {e["params"]["requestId"] for e in self.events
                     if e.get("method") in ("Network.loadingFinished", "Network.loadingFailed")}
            new = [e for e in self.events[before:] if e.get("method") == "Network.requestWillBeSent"]
            if loaded and started <= ended and not new:
                return list(self.events)
        raise RuntimeError("%s did not finish loading" % url)

    def close(self):
        try:
            self.call("Browser.close")
        except Exception:  # noqa: BLE001 - it may close the socket before it answers
            pass
        try:
            self.process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self.stderr.close()


@pytest.fixture(scope="module")
def browser():
    with tempfile.TemporaryDirectory() as profile:
        chromium = Chromium(profile)
        chromium.tab("Emulation.setDeviceMetricsOverride", width=1280, height=900,
                     deviceScaleFactor=1, mobile=False)
        yield chromium
        chromium.close()


def problems(events):
    """What a reader would see go wrong: missing resources, console errors, exceptions."""
    found = []
    for event in events:
        method, params = event.get("method"), event.get("params", {})
        if method == "Network.responseReceived" and params["response"]["status"] >= 400:
            found.append("HTTP %d: %s" % (params["response"]["status"], params["response"]["url"]))
        elif method == "Network.loadingFailed" and not params.get("canceled"):
            found.append("request failed (%s)" % params.get("errorText"))
        elif method == "Runtime.exceptionThrown":
            details = params["exceptionDetails"]
            found.append("exception: %s" % details.get("exception", {}).get("description",
                                                                              details.get("text")))
        elif method == "Runtime.consoleAPICalled" and params["type"] in ("error", "assert"):
            found.append("console %s: %s" % (params["type"], [a.get("value") for a in params["args"]]))
        elif method == "Log.entryAdded" and params["entry"]["level"] == "error":
            found.append("log: %s %s" % (params["entry"]["text"], params["entry"].get("url", "")))
    return found


@pytest.mark.parametrize("page", list(PAGES))
def test_page_loads_whole(page, server, browser):
    base, log = server
    del log[:]
    events = browser.load(base + page)
    assert problems(events) == [], page
    assert [entry for entry in log if entry[1] >= 400] == [], "the server's log of " + page
    requested = {urllib.parse.urlsplit(e["params"]["request"]["url"]).path for e in events
                 if e.get("method") == "Network.requestWillBeSent"}
    assert len(requested) >= 5, "the page, its stylesheets and scripts: %s" % sorted(requested)
    assert browser.evaluate(STYLED), "the theme's stylesheet is applied on " + page
    assert browser.evaluate(PAGES[page]), "the content of " + page
    if page == "docs/index.html":
        shot = browser.tab("Page.captureScreenshot", format="png")["data"]
        import base64

        with open(os.path.join(os.path.dirname(HTML), "index.png"), "wb") as f:
            f.write(base64.b64decode(shot))


def test_search_finds_neighborlist(server, browser):
    base, log = server
    del log[:]
    events = browser.load(base + "search.html?q=NeighborList")
    results = None
    deadline = time.time() + 60
    while time.time() < deadline:
        results = browser.evaluate(
            "({summary: (document.querySelector('#search-results > p') || {}).innerText || '',"
            " items: Array.from(document.querySelectorAll('#search-results li'))"
            ".map(li => li.innerText)})")
        if results["summary"].startswith("Search finished"):
            break
        browser.pump(0.25)
    else:
        pytest.fail("the search did not finish: %s" % results)
    events += browser.events
    assert problems(events) == []
    assert [entry for entry in log if entry[1] >= 400] == []
    items = "\n".join(results["items"])
    assert "tricell.NeighborList (Python class" in items, items
    assert "tricell::NeighborList (C++ class" in items, items


class Links(html.parser.HTMLParser):
    """The ids of a page and the targets of its links, stylesheets, scripts and images."""

    def __init__(self):
        super().__init__()
        self.ids, self.targets = set(), []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        for name in ("id", "name") if tag == "a" else ("id",):
            if attrs.get(name):
                self.ids.add(attrs[name])
        for name in ("href", "src"):
            if attrs.get(name):
                self.targets.append(attrs[name])


def test_every_internal_link_resolves():
    pages = {}
    for folder, _, names in os.walk(HTML):
        for name in names:
            if name.endswith(".html"):
                path = os.path.relpath(os.path.join(folder, name), HTML).replace(os.sep, "/")
                parser = Links()
                with open(os.path.join(folder, name), encoding="utf-8") as f:
                    parser.feed(f.read())
                pages[path] = parser
    assert "docs/index.html" in pages and len(pages) > 20, sorted(pages)
    broken, checked = [], 0
    for path, parser in pages.items():
        for target in parser.targets:
            parts = urllib.parse.urlsplit(target)
            if parts.scheme or parts.netloc or target.startswith(("mailto:", "javascript:")):
                continue
            checked += 1
            resolved = posixpath.normpath(posixpath.join(posixpath.dirname(path),
                                                         urllib.parse.unquote(parts.path))) \
                if parts.path else path
            if resolved.endswith("/") or os.path.isdir(os.path.join(HTML, resolved)):
                resolved = posixpath.join(resolved, "index.html")
            if not os.path.isfile(os.path.join(HTML, resolved)):
                broken.append("%s: %s (no file %s)" % (path, target, resolved))
            elif parts.fragment and resolved in pages and \
                    urllib.parse.unquote(parts.fragment) not in pages[resolved].ids:
                broken.append("%s: %s (no id %s in %s)" % (path, target, parts.fragment, resolved))
    assert broken == [], "\n".join(broken)
    assert checked > 1000, checked
