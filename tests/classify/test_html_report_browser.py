"""The HTML report opens in a headless browser without errors, and its images are present (issue 14).

The page is the one ``closedchain report --html`` writes, here for the
five-bar (a drawing per configuration and the loci map of a 2-dof design).
Chromium is the system's (Debian's ``chromium`` package, which ``.ci/run``
installs where it can); without it the test is skipped, naming why.

How the page is checked, with Chromium alone (no driver): a copy of the page
gets one script at the very top of its ``<head>`` that records every error
(``window.onerror``, failed resources) and, once the page has loaded, whether
each ``<img>`` decoded to a picture of nonzero size; the script writes its
findings as JSON into an element that ``--dump-dom`` prints. The report
itself is not changed.
"""

import json
import re
import shutil
import subprocess
import sys

import pytest

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no Chromium on this machine (Debian package 'chromium')")

#: flags of a headless start on a machine with no network (no background connections, no first-run work)
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--allow-file-access-from-files", "--virtual-time-budget=20000")

PROBE = """<script>
(function () {
  var errors = [];
  window.addEventListener("error", function (event) {
    var target = event.target;
    errors.push(target && target.tagName ? "resource " + target.tagName + " failed"
                                         : String(event.message));
  }, true);
  window.addEventListener("load", function () {
    var images = Array.prototype.map.call(document.images, function (image) {
      return {complete: image.complete, width: image.naturalWidth, height: image.naturalHeight,
              alt: image.alt};
    });
    var out = document.createElement("pre");
    out.id = "probe-result";
    out.textContent = JSON.stringify({errors: errors, images: images, title: document.title});
    document.body.appendChild(out);
  });
})();
</script>"""


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    """The five-bar's HTML report, as the command writes it."""
    folder = tmp_path_factory.mktemp("report")
    html = folder / "report.html"
    finished = subprocess.run([sys.executable, "-m", "classify", "report", "five-bar", "--jobs", "1",
                               "--output", str(folder / "report.txt"), "--html", str(html)],
                              capture_output=True, text=True, timeout=600)
    assert finished.returncode == 0, finished.stderr
    return html


def _open(html, folder):
    """What the probe found when Chromium loaded a copy of `html`."""
    document = html.read_text(encoding="utf-8")
    probed = folder / "probed.html"
    probed.write_text(re.sub(r"<head>", lambda match: match.group(0) + PROBE, document, count=1),
                      encoding="utf-8")
    finished = subprocess.run([CHROMIUM, *FLAGS, f"--user-data-dir={folder / 'profile'}", "--dump-dom",
                               probed.as_uri()], capture_output=True, text=True, timeout=180)
    assert finished.returncode == 0, finished.stderr[-2000:]
    found = re.search(r'<pre id="probe-result">(.*?)</pre>', finished.stdout, re.S)
    assert found, "the page did not finish loading in Chromium"
    text = found.group(1).replace("&quot;", '"').replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&")
    return json.loads(text)


def test_the_report_opens_without_errors_and_every_image_is_decoded(page, tmp_path):
    result = _open(page, tmp_path)
    assert result["errors"] == []
    images = result["images"]
    # one drawing per five-bar configuration and its loci map: several pictures, all decoded
    expected = len(re.findall(r"<img ", page.read_text(encoding="utf-8")))
    assert expected >= 2
    assert len(images) == expected
    assert all(image["complete"] and image["width"] > 0 and image["height"] > 0 for image in images), images


def test_a_broken_image_is_seen_by_the_probe(page, tmp_path):
    """The check can fail: a picture whose data is not a PNG is reported."""
    broken = tmp_path / "broken.html"
    document = page.read_text(encoding="utf-8")
    broken.write_text(re.sub(r'src="data:image/png;base64,[^"]{8}', 'src="data:image/png;base64,AAAAAAAA', document,
                             count=1), encoding="utf-8")
    result = _open(broken, tmp_path)
    assert result["errors"] or not all(image["width"] > 0 for image in result["images"])
