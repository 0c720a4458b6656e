#!/usr/bin/env python3
"""ecat-slave --http in headless chromium (tests/scripts/web_browser.sh).

5 drives over UDP on loopback, ecat-master bringing them to Op and cycling;
the page must show 5 slaves in Op, cut the cable between slave #2 and #3 at a
click, show both ends' link down, engage a drive fault on slave #1 from the
fault form and show that drive in Fault with its emergency, clear it and
restore the cable at a click and show the link up again; ecat-master must
have counted WKC errors meanwhile. Every wait polls with a generous
deadline; no sleep decides an outcome.

--slaves, --cut and --drive-fault make the same run on another network (the
20-drive walkthrough of docs/webview.md: --slaves 20 --cut 7 --drive-fault 3);
--describe prints what the page shows in words at the screenshot.
"""
import argparse
import json
import re
import socket
import subprocess
import sys
import time
import urllib.request

from selenium import webdriver
from selenium.common.exceptions import StaleElementReferenceException, WebDriverException
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By

CUT_PORT, PEER_PORT = 1, 0     # the cut slave's port 1 goes on to the next slave's port 0
DRIVE_FAULT_CODE = 0x2310       # over-current (CiA 402 603Fh, the EMCY's error code)
MASTER_CYCLES = 20000           # 1 ms each: the master runs while the page acts


OUTPUT = {}  # what ecat-slave and ecat-master printed, shown on failure


def free_port(kind):
    with socket.socket(socket.AF_INET, kind) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_until(what, condition, timeout):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            value = condition()
            if value:
                return value
        except (StaleElementReferenceException, OSError, ValueError):
            pass  # the page redrew, or the server is not up yet: ask again
        time.sleep(0.1)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def api(url, request):
    req = urllib.request.Request(url + "api", data=json.dumps(request).encode(),
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=10) as r:
        return json.loads(r.read())["result"]


def click(driver, css, what):
    def attempt():
        found = driver.find_elements(By.CSS_SELECTOR, css)
        if not found:
            return False
        try:
            found[0].click()
        except WebDriverException:  # redrawn or covered just now: ask again
            return False
        return True
    wait_until(f"{what} ({css}) to be clickable", attempt, 20)


def link(driver, slave, port):
    # One script reads the attribute where it finds the element: the page
    # redraws a card between a find and a read, and a held element goes stale.
    css = f'#slaves .card[data-slave="{slave}"] .port[data-port="{port}"]'
    return driver.execute_script(
        "const e = document.querySelector(arguments[0]); return e ? e.getAttribute('data-link') : null;", css)


def cia402_state(driver):
    return driver.execute_script(
        "const s = document.querySelector('#detail [data-axis] [data-cia402]'); return s ? s.dataset.cia402 : null;")


def describe(driver):
    """What a person reads on the page, panel by panel (--describe)."""
    return driver.execute_script(r"""
        const text = (sel) => { const e = document.querySelector(sel); return e ? e.innerText.trim() : '(none)'; };
        const states = {};
        for (const c of document.querySelectorAll('#slaves .card')) states[c.dataset.state] = (states[c.dataset.state] || 0) + 1;
        return 'slave cards by state: ' + JSON.stringify(states) + '\n--- topology:\n' + text('#topology') +
               '\n--- selected slave:\n' + text('#detail') + '\n--- frames:\n' + text('#frames') +
               '\n--- faults engaged:\n' + text('#faults-engaged') + '\n--- events:\n' + text('#events');""")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--slave", required=True)
    ap.add_argument("--master", required=True)
    ap.add_argument("--screenshot", required=True)
    ap.add_argument("--slaves", type=int, default=5)
    ap.add_argument("--cut", type=int, default=2, help="the slave whose port 1 is cut")
    ap.add_argument("--drive-fault", type=int, default=1, help="the slave whose drive faults")
    ap.add_argument("--window", default="1100,1500")
    ap.add_argument("--describe", action="store_true")
    a = ap.parse_args()
    SLAVES, CUT_SLAVE, PEER_SLAVE, FAULT_SLAVE = a.slaves, a.cut, a.cut + 1, a.drive_fault
    assert 0 <= FAULT_SLAVE < SLAVES and 0 <= CUT_SLAVE < SLAVES - 1, "--cut/--drive-fault outside the network"
    started = time.monotonic()
    udp, http = free_port(socket.SOCK_DGRAM), free_port(socket.SOCK_STREAM)
    url = f"http://127.0.0.1:{http}/"
    slave = subprocess.Popen([a.slave, "--udp", str(udp), "--count", str(SLAVES), "--http", str(http), "-q"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    master = driver = None
    try:
        wait_until("ecat-slave's page", lambda: urllib.request.urlopen(url, timeout=2).status == 200, 30)
        master = subprocess.Popen([a.master, "--udp", f"127.0.0.1:{udp}", "--cycles", str(MASTER_CYCLES),
                                   "--recover", "-q"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        options = webdriver.ChromeOptions()
        options.binary_location = "/usr/bin/chromium"
        for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                    f"--window-size={a.window}"):
            options.add_argument(arg)
        driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
        driver.set_page_load_timeout(30)
        driver.get(url)
        wait_until(f"{SLAVES} slaves in OP on the page", lambda: len(driver.find_elements(
            By.CSS_SELECTOR, '#slaves .card[data-state="OP"]')) == SLAVES, 40)
        print(f"page: {SLAVES} slaves in OP after {time.monotonic() - started:.1f} s")
        # The master's cycles as the slaves see them, with their lateness histogram.
        wait_until("cycles and on-time cycles counted on the page", lambda: int(driver.execute_script(
            "const c = document.querySelector('#lateness [data-frames=cycles]');"
            "const t = document.querySelector('#lateness tr[data-lateness=on_time] td.num');"
            "return c && t ? Math.min(Number(c.textContent), Number(t.textContent.trim())) : 0;")) > 0, 20)
        wait_until("both ends of the cable to cut shown up", lambda: link(driver, CUT_SLAVE, CUT_PORT) == "up"
                   and link(driver, PEER_SLAVE, PEER_PORT) == "up", 20)

        assert master.poll() is None, "ecat-master ended before the cable was cut (host too slow?)"
        click(driver, f'#topology button.cut[data-slave="{CUT_SLAVE}"][data-port="{CUT_PORT}"]', "Cut cable")
        wait_until("both ends of the cut cable shown down", lambda: link(driver, CUT_SLAVE, CUT_PORT) == "down"
                   and link(driver, PEER_SLAVE, PEER_PORT) == "down", 20)
        wait_until("the cut marked in the tree", lambda: driver.find_elements(
            By.CSS_SELECTOR, f'#topology [data-cut="{CUT_SLAVE}:{CUT_PORT}"]'), 20)
        print("page: cable cut, both ends down")
        # The same counters through the control interface: a lost link at each end.
        net = api(url, {"cmd": "network"})
        assert net["slaves"][CUT_SLAVE]["ports"][CUT_PORT]["lost_links"] >= 1, net["slaves"][CUT_SLAVE]
        assert net["slaves"][PEER_SLAVE]["ports"][PEER_PORT]["lost_links"] >= 1, net["slaves"][PEER_SLAVE]
        click(driver, f'#slaves .card[data-slave="{PEER_SLAVE}"]', "the card of the slave behind the cut")
        # Its drive section: one axis, its CiA 402 state in words and three plots.
        wait_until("the drive section of the slave shown", lambda: driver.execute_script(
            "const a = document.querySelectorAll('#detail [data-axis]');"
            "if (a.length !== 1 || a[0].dataset.axis !== '1') return false;"
            "const s = a[0].querySelector('[data-cia402]');"
            "return !!s && s.dataset.cia402 !== 'unknown' && a[0].querySelectorAll('canvas').length === 3;"), 20)

        # A drive fault from the page's fault form (item 3): the drive shows
        # Fault in words, its emergency arrives, the engaged list has it.
        click(driver, f'#slaves .card[data-slave="{FAULT_SLAVE}"]', "the card of the slave to fault")
        # Whatever state the master left it in (it may be recovering the slaves behind the cut), not Fault.
        wait_until("the selected drive's CiA 402 state, not Fault", lambda: cia402_state(driver) not in
                   (None, "unknown", "Fault"), 20)
        driver.execute_script(
            "const k = document.getElementById('fault-kind'); k.value = 'drive_fault';"
            "k.dispatchEvent(new Event('change'));")
        driver.execute_script(
            "const f = document.getElementById('fault-kind').form;"
            "f.querySelector('select[name=slave]').value = arguments[0];"
            "f.querySelector('input[name=param-code]').value = arguments[1];", str(FAULT_SLAVE), hex(DRIVE_FAULT_CODE))
        click(driver, "#fault-engage", "Engage")
        wait_until("the faulted drive in Fault on the page", lambda: cia402_state(driver) == "Fault", 20)
        emcy = f"0x{DRIVE_FAULT_CODE:04X}"
        wait_until(f"the EMCY {emcy} listed for the slave", lambda: emcy in driver.execute_script(
            "return document.getElementById('detail').innerText;"), 20)
        wait_until("the drive fault in the engaged list", lambda: f"drive_fault slave #{FAULT_SLAVE}" in
                   driver.execute_script("return document.getElementById('faults-engaged').innerText;"), 20)
        print(f"page: drive fault {emcy} on #{FAULT_SLAVE} shown (Fault, EMCY, engaged list)")
        time.sleep(1.0)  # only for the picture: a few plot samples
        driver.execute_script("window.scrollTo(0, 0);")  # the form's click scrolled down
        driver.save_screenshot(a.screenshot)
        print(f"screenshot: {a.screenshot}")
        if a.describe:
            print(describe(driver))
        def clear_drive_fault():
            found = driver.find_elements(By.XPATH, "//ul[@id='faults-engaged']/li[contains(., 'drive_fault')]/button")
            if not found:
                return False
            try:
                found[0].click()
            except WebDriverException:
                return False
            return True
        wait_until("Clear of the drive fault to be clickable", clear_drive_fault, 20)
        wait_until("the drive fault cleared", lambda: not [f for f in api(url, {"cmd": "faults"})["faults"]
                                                          if f["kind"] == "drive_fault"], 20)

        click(driver, f'#topology button.restore[data-slave="{CUT_SLAVE}"][data-port="{CUT_PORT}"]',
              "Restore cable")
        wait_until("both ends up again", lambda: link(driver, CUT_SLAVE, CUT_PORT) == "up"
                   and link(driver, PEER_SLAVE, PEER_PORT) == "up", 20)
        print("page: cable restored, both ends up")
        assert api(url, {"cmd": "faults"})["faults"] == []

        out, _ = master.communicate(timeout=90)
        m = re.search(r"cycles (\d+) lost (\d+) wkc-errors (\d+)", out)
        assert m, f"no summary from ecat-master:\n{out}"
        assert int(m.group(3)) > 0, f"ecat-master counted no WKC errors:\n{out}"
        print(f"ecat-master: {m.group(0)}")
        print(f"ok in {time.monotonic() - started:.1f} s")
        return 0
    finally:
        if driver:
            try:
                driver.quit()
            except WebDriverException:
                pass
        for p in (master, slave):
            if p and p.poll() is None:
                p.terminate()
                try:
                    p.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    p.kill()
        for name, p in (("ecat-master", master), ("ecat-slave", slave)):
            if p and p.stdout and not p.stdout.closed:
                try:
                    OUTPUT[name] = p.stdout.read()
                except (OSError, ValueError):
                    pass


if __name__ == "__main__":
    try:
        sys.exit(main())
    except AssertionError as e:
        print(f"FAIL: {e}")
        for name, text in OUTPUT.items():
            print(f"--- {name}:\n{text}")
        sys.exit(1)
