"""The addon's metadata (package.xml, read by FreeCAD's Addon Manager) against pyproject.toml, and the
addon's two FreeCAD entries (Init.py for every FreeCAD process, InitGui.py for the GUI)."""
import os
import re
import xml.etree.ElementTree as ET

from conftest import ROOT

NS = {"p": "https://wiki.freecad.org/Package_Metadata"}


def test_package_xml_matches_pyproject():
    root = ET.parse(os.path.join(ROOT, "package.xml")).getroot()
    urls = {u.get("type"): u for u in root.findall("p:url", NS)}
    assert {"repository", "bugtracker", "readme"} <= set(urls)
    assert urls["repository"].get("branch") == "main" and urls["repository"].text.startswith("https://")
    assert len(root.findall("p:tag", NS)) >= 3
    py = open(os.path.join(ROOT, "pyproject.toml")).read()
    version = re.search(r'^version = "([^"]+)"', py, re.M).group(1)
    assert root.find("p:version", NS).text == version
    deps = re.search(r"^dependencies = \[(.*)\]", py, re.M).group(1)
    wanted = dict(re.findall(r'"([a-z]+)>=([0-9.]+)"', deps))
    have = {d.text: d.get("version_gte") for d in root.findall("p:depend", NS) if d.get("optional") != "true"}
    assert have == wanted
    for entry in ("Init.py", "InitGui.py", root.find("p:icon", NS).text):
        assert os.path.isfile(os.path.join(ROOT, entry)), entry
