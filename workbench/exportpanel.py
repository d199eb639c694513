"""Export for machining in one task panel, and the workbench's preferences page.

The panel asks the format, the file and every setting of the machine data at once (units, chord
tolerance, kerf, side, machine axis and planes, feed, lead-in, tool radius and taper, a STEP for CAM), with
the options that do not apply to the format disabled.  Its values are kept in FreeCAD's parameters
(User parameter:BaseApp/Preferences/Mod/Ruled/Export) when it writes, and fill it the next time, also
after a restart; the preferences page (Edit > Preferences > Ruled) edits the same values and the
defaults of new fits.  The files are the command line's: ``ruled machine`` with the same settings.
"""

from __future__ import annotations

import os

import FreeCAD
from PySide import QtGui

from .qtcompat import standard_buttons

EXPORT_GROUP = "User parameter:BaseApp/Preferences/Mod/Ruled/Export"
FIT_GROUP = "User parameter:BaseApp/Preferences/Mod/Ruled/Fit"

MACHINE = ("xyuv", "flank")
ACTIVE = None            # the open export panel (for scripts and tests)
SPECIAL = {"ChordTol": "auto", "Kerf": "none", "Lead": "auto", "GougeTol": "auto", "WirePower": "post's",
           "Dwell": "post's"}  # what a box's lowest value means
WIRE_POSTS = ("linuxcnc", "grbl", "iso-wedm", "apt-sync")       # (ruled.machine.posts.SHIPPED, a wire's)
# name, kind, default, the formats it applies to, label, tooltip
SETTINGS = [
    ("Post", WIRE_POSTS, "linuxcnc", ("xyuv",), "Post", "the controller the G-code is written for: linuxcnc "
     "(RS274/NGC, X Y U V, AXIS's foam preview), grbl (GRBL, FluidNC, grblHAL foam cutters: X Y Z A), iso-wedm "
     "(Fanuc-family 4-axis wire EDM: U V relative), apt-sync (APT CL for a commercial wire post); the command line's "
     "--post"),
    ("PostFile", "text", "", ("xyuv",), "Own post file", "your own post: the path of a .toml (a shipped post copied "
     "and changed; 'ruled posts NAME' prints one); empty: the post above"),
    ("FeedMode", ("post's", "g93", "g94"), "post's", ("xyuv",), "Feed mode", "g93: inverse time, each move's time from "
     "its longer guide at the feed (the faster guide runs at the feed); g94: units per minute along X Y; post's: the "
     "post's own"),
    ("WirePower", "power", 0.0, ("xyuv",), "Wire power", "a hot wire's power: M3 S<power> before the cut, M5 after "
     "(post's: the post's own; none for linuxcnc)"),
    ("Dwell", "seconds", -1.0, ("xyuv",), "Dwell", "seconds the wire heats (G4 P) before the first move (post's: the "
     "post's own)"),
    ("Letters", "text", "", ("xyuv",), "Axis letters", "the letters of lower X, lower Y, upper X, upper Y, e.g. XYZA "
     "(empty: the post's)"),
    ("Home", "bool", False, ("xyuv",), "Home first", "home the machine first (the post's homing: $H, G28)"),
    ("Origin", "bool", False, ("xyuv",), "G92 origin", "the wire stands at the path's first point: G92 declares it "
     "there (iso-wedm: always)"),
    ("Compensation", "text", "", ("xyuv",), "Wire compensation", "wire EDM: the controller's D register (G41/G42 D, "
     "with the uncompensated path; leave Kerf at none); empty: Ruled offsets the wire by the kerf"),
    ("Units", ("mm", "inch"), "mm", MACHINE, "Units", "units of the G-code / APT / CSV coordinates (the model's are "
     "mm; G21 or G20, UNITS/MM or UNITS/INCHES)"),
    ("ChordTol", "length", 0.0, MACHINE + ("step-rulings",), "Chord tolerance", "largest distance between a straight "
     "move and the contours (auto: 1e-4 of the part's size)"),
    ("Kerf", "length", 0.0, ("xyuv",), "Kerf", "wire radius plus spark gap: the wire runs offset by it to the side "
     "below (0: none)"),
    ("Side", ("auto", "outside", "inside"), "auto", MACHINE, "Side", "the side the wire's kerf or the tool is on: "
     "of a face, outside is its normal's side (auto: outside); of a wall, outside or inside its contour (auto: off "
     "the material, outside a punch, inside a hole)"),
    ("Axis", "text", "", ("xyuv",), "Machine axis", "the machine axis, normal to the guide planes: x, y, z or a "
     "vector ax, ay, az (empty: auto, the rulings' mean direction, snapped to x, y or z within 0.5 degree)"),
    ("Planes", "text", "", ("xyuv",), "Machine planes", "the two guide plane heights a, b along the machine axis, in "
     "mm (empty: just outside the part)"),
    ("Lead", "lead", -1.0, ("xyuv",), "Lead-in", "lead-in and lead-out length (auto: 5 % of the part's size; 0: "
     "none)"),
    ("Feed", "float", 100.0, MACHINE, "Feed", "feed rate, output units per minute"),
    ("ToolRadius", "length", 5.0, ("flank",), "Tool radius", "flank milling: the tool's radius (at the tip for a "
     "tapered tool)"),
    ("Taper", "angle", 0.0, ("flank",), "Tool taper", "flank milling: half angle of a conical tool (0: cylindrical)"),
    ("ToolPositions", ("envelope", "offset"), "envelope", ("flank",), "Tool positions", "flank milling: envelope: "
     "the tool's positions fitted so the swept tool fits the face, its overcut within the gouge tolerance; offset: "
     "each ruling offset by the tool radius (exact on cylinders and cones only)"),
    ("GougeTol", "length", 0.0, ("flank",), "Gouge tolerance", "flank milling, envelope positions: the overcut "
     "allowed, the moves between CL points included (auto: the fit's bound)"),
    ("CornerRadius", "length", 0.0, ("flank",), "Corner radius", "flank milling: the tool's corner radius, in APT's "
     "CUTTER (0: a flat end)"),
    ("CamStep", "bool", False, MACHINE, "STEP for CAM", "also write a STEP beside the file: the ruled face and its "
     "rulings at the synchronized points"),
]


def _group(path: str = EXPORT_GROUP):
    return FreeCAD.ParamGet(path)


def load_settings() -> dict:
    """The remembered export settings (the defaults where none is remembered yet)."""
    g = _group()
    out = {"Format": g.GetString("Format", "xyuv"), "Path": g.GetString("Path", "")}
    for name, kind, default, *_ in SETTINGS:
        if kind == "bool":
            out[name] = g.GetBool(name, default)
        elif isinstance(kind, tuple) or kind == "text":
            out[name] = g.GetString(name, default)
        else:
            out[name] = g.GetFloat(name, default)
    return out


def save_settings(values: dict) -> None:
    """Remember the settings in FreeCAD's parameters and write them to the user's configuration now."""
    g = _group()
    for name, x in values.items():
        if isinstance(x, bool):
            g.SetBool(name, x)
        elif isinstance(x, str):
            g.SetString(name, x)
        else:
            g.SetFloat(name, float(x))
    try:
        FreeCAD.saveParameter()            # kept even if FreeCAD does not exit normally
    except Exception:  # older FreeCAD: written at exit
        pass


def machine_params(v: dict, kind: str) -> dict:
    """The settings as keyword arguments of workbench.export.export for the format kind."""
    from ruled.core.errors import BadInputError
    if kind not in MACHINE:
        return {"chord_tol": v["ChordTol"] or None} if kind == "step-rulings" else {}
    planes = None
    if v["Planes"].strip():
        try:
            planes = [float(x) for x in v["Planes"].replace(";", ",").split(",")]
        except ValueError:
            raise BadInputError(f"machine planes {v['Planes']!r}: give two heights a, b in mm, or leave it empty") \
                from None
    out = {"chord_tol": v["ChordTol"] or None, "side": v["Side"], "feed": v["Feed"], "units": v["Units"],
           "settings": post_settings(v, kind)}
    if kind == "xyuv":
        out.update(kerf=v["Kerf"], planes=planes, lead=None if v["Lead"] < 0 else v["Lead"],
                   axis=v["Axis"].strip().replace(";", ",") or "auto")
    else:
        out.update(tool_radius=v["ToolRadius"], taper=v["Taper"], positions=v["ToolPositions"],
                   gouge_tol=v["GougeTol"] or None)
    return out


def post_settings(v: dict, kind: str):
    """The post and its settings (ruled.machine.program.PostSettings) the panel's values say, checked against each
    other (one line naming the setting where they cannot be written)."""
    from ruled.core.errors import BadInputError
    from ruled.machine.program import PostSettings
    if kind != "xyuv":
        return PostSettings(corner_radius=v["CornerRadius"])
    comp = v["Compensation"].strip()
    if comp and not comp.isdigit():
        raise BadInputError(f"wire compensation {comp!r}: give the controller's D register, a whole number, or leave "
                            f"it empty")
    if comp and v["Kerf"]:
        raise BadInputError("wire compensation lets the controller offset the wire by its D register; Kerf offsets it "
                            "in the path: set one of them")
    s = PostSettings(post=v["PostFile"].strip() or v["Post"],
                     feed_mode=None if v["FeedMode"] == "post's" else v["FeedMode"],
                     power=v["WirePower"] or None, dwell=None if v["Dwell"] < 0 else v["Dwell"],
                     letters=v["Letters"].strip() or None, home=v["Home"], origin=True if v["Origin"] else None,
                     compensation=int(comp) if comp else None)
    s.resolved("xyuv")
    return s


def _widget(kind):
    if isinstance(kind, tuple):
        w = _combo(list(kind))
    elif kind == "bool":
        w = QtGui.QCheckBox()
    elif kind == "text":
        w = QtGui.QLineEdit()
        w.setPlaceholderText("auto")
    else:
        w = QtGui.QDoubleSpinBox()
        w.setDecimals(4)
        w.setRange(-1.0 if kind in ("lead", "seconds") else 0.0, 90.0 if kind == "angle" else 100000.0)
        w.setSuffix({"angle": " deg", "float": " /min", "seconds": " s", "power": ""}.get(kind, " mm"))
    return w


def _combo(items) -> QtGui.QComboBox:
    """A combo box as narrow as the side panel needs (its long entries elided, the list at full width)."""
    w = QtGui.QComboBox()
    w.addItems(items)
    w.setSizeAdjustPolicy(QtGui.QComboBox.AdjustToMinimumContentsLengthWithIcon)
    w.setMinimumContentsLength(8)
    w.view().setMinimumWidth(w.view().sizeHintForColumn(0) + 20)
    return w


def _get(w):
    if isinstance(w, QtGui.QComboBox):
        return w.currentText()
    if isinstance(w, QtGui.QCheckBox):
        return bool(w.isChecked())
    if isinstance(w, QtGui.QLineEdit):
        return w.text()
    return float(w.value())


def _put(w, x):
    if isinstance(w, QtGui.QComboBox):
        w.setCurrentIndex(max(0, w.findText(x)))
    elif isinstance(w, QtGui.QCheckBox):
        w.setChecked(bool(x))
    elif isinstance(w, QtGui.QLineEdit):
        w.setText(x)
    else:
        w.setValue(float(x))


def settings_rows(lay) -> dict:
    """The settings' widgets added to a form layout (name -> widget), with tooltips."""
    out = {}
    for name, kind, _default, _formats, label, tip in SETTINGS:
        w = _widget(kind)
        w.setToolTip(tip)
        if name in SPECIAL:
            w.setSpecialValueText(SPECIAL[name])
        lay.addRow(label, w)
        out[name] = w
    return out


class ExportTaskPanel:
    """Format, file and settings at once; OK writes (the panel stays open with the reason when it cannot)."""

    def __init__(self, objects):
        global ACTIVE
        from .export import FORMATS
        ACTIVE = self
        self.objects = objects
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Export for machining")
        lay = QtGui.QFormLayout(self.form)
        lay.setFieldGrowthPolicy(QtGui.QFormLayout.AllNonFixedFieldsGrow)
        self.kinds = list(FORMATS.values())
        self.format = _combo([k.split(" (")[0] for k in FORMATS])
        self.format.setToolTip("what to write: the ruled faces as STEP (with their rulings as edges), XYUV G-code for "
                               "a 4-axis wire, or flank-milling CL data (APT); a CSV and a JSON report go beside "
                               "machine data")
        lay.addRow("Format", self.format)
        row = QtGui.QHBoxLayout()
        self.path = QtGui.QLineEdit()
        self.path.setToolTip("the file to write (its folder must exist)")
        browse = QtGui.QPushButton("...")
        browse.setToolTip("choose the file")
        browse.setMaximumWidth(32)
        row.addWidget(self.path)
        row.addWidget(browse)
        lay.addRow("File", row)
        self.widgets = settings_rows(lay)
        self.write_button = QtGui.QPushButton("Write")
        self.write_button.setToolTip("write the file with these settings and show the cut's figures here (the panel "
                                     "stays open; OK writes and closes)")
        self.write_button.clicked.connect(self.write)
        lay.addRow(self.write_button)
        self.result = QtGui.QLabel("")
        self.result.setWordWrap(True)
        lay.addRow(self.result)
        v = load_settings()
        if v["Format"] in self.kinds:
            self.format.setCurrentIndex(self.kinds.index(v["Format"]))
        for name, w in self.widgets.items():
            _put(w, v[name])
        self.path.setText(self._default_path(v["Path"]))
        browse.clicked.connect(self._browse)
        self.format.currentIndexChanged.connect(self._format_changed)
        self.widgets["Post"].currentIndexChanged.connect(self._format_changed)
        self._format_changed()

    def kind(self) -> str:
        return self.kinds[self.format.currentIndex()]

    def _default_path(self, last: str) -> str:
        folder = os.path.dirname(last) if last else os.path.expanduser("~")
        name = self.objects[0].Label if self.objects else "ruled"
        return os.path.join(folder, name + self._suffix())

    def _suffix(self) -> str:
        """The chosen format's file name ending (a wire's: its post's, .ngc for linuxcnc, .gcode for grbl, ...)."""
        if self.kind() == "xyuv":
            from ruled.core.errors import RuledError
            from ruled.machine.posts import load_post
            spec = self.widgets["PostFile"].text().strip() or self.widgets["Post"].currentText()
            try:
                return load_post(spec).extension
            except RuledError:          # (a post file that does not load: said when writing)
                return ".ngc"
        return {"flank": ".apt"}.get(self.kind(), ".step")

    following = False

    def _format_changed(self, *_):
        """Only the settings of the chosen format are enabled; the file's extension follows the format (unless the
        format is following the file's extension, write)."""
        kind = self.kind()
        for name, _k, _d, formats, *_ in SETTINGS:
            self.widgets[name].setEnabled(kind in formats)
        base, ext = os.path.splitext(self.path.text())
        if base and not self.following and ext.lower() in (".ngc", ".nc", ".gcode", ".apt", ".cls", ".step", ".stp",
                                                           ""):
            self.path.setText(base + self._suffix())

    @staticmethod
    def _kind_of(path: str, chosen: str) -> str:
        """The format a file's extension names (.ngc/.nc/.gcode: XYUV, .apt/.cls: flank, but .apt XYUV with XYUV
        chosen: apt-sync's; .step/.stp: STEP), else the chosen one (either STEP for a STEP file)."""
        ext = os.path.splitext(path)[1].lower()
        named = {".ngc": "xyuv", ".nc": "xyuv", ".gcode": "xyuv", ".cls": "flank",
                 ".apt": "xyuv" if chosen == "xyuv" else "flank"}.get(ext)
        if ext in (".step", ".stp"):
            return chosen if chosen.startswith("step") else "step"
        return named or chosen

    def _browse(self):
        from .export import FORMATS
        name = list(FORMATS)[self.format.currentIndex()]
        path, _ = QtGui.QFileDialog.getSaveFileName(None, "Export for machining", self.path.text(), name)
        if path:
            self.path.setText(path)

    def values(self) -> dict:
        out = {name: _get(w) for name, w in self.widgets.items()}
        out.update(Format=self.kind(), Path=self.path.text())
        return out

    def write(self) -> bool:
        """Write the file with the panel's settings; remember them.  False (and the reason shown) when it
        cannot."""
        from ruled.core.errors import RuledError

        from .export import export
        from .features import in_our_terms
        v = self.values()
        path = v["Path"].strip()
        if not path or not os.path.isdir(os.path.dirname(os.path.abspath(path))):
            self.result.setText(f"Cannot write {path or 'nothing'}: choose a file in an existing folder")
            return False
        kind, said = self._kind_of(path, v["Format"]), ""
        if kind != v["Format"]:
            # the file's extension names another format (wall.ngc with STEP chosen): the format follows it
            from .export import FORMATS
            self.following = True
            self.format.setCurrentIndex(self.kinds.index(kind))
            self.following = False
            v = self.values()
            said = (f"The format follows the file's extension {os.path.splitext(path)[1]}: "
                    f"{[k for k, x in FORMATS.items() if x == kind][0].split(' (')[0]}. ")
        try:
            params = machine_params(v, kind)
            if kind in MACHINE and v["CamStep"]:
                params["cam_step"] = os.path.splitext(path)[0] + "_cam.step"
            rep = export(self.objects, path, kind, **params)
        except RuledError as exc:
            self.result.setText(f"Cannot export: {in_our_terms(exc)}")
            return False
        except Exception as exc:  # Part's OCCError, OSError on write failures
            self.result.setText(f"Cannot write {path}: {exc}")
            return False
        save_settings(v)
        self.written = path
        figures = said + wrote_text(path, rep)
        FreeCAD.Console.PrintMessage(f"Ruled: {figures}\n")
        self.result.setText(figures)
        self.fallback = bool(rep and rep.get("fallback"))
        if self.fallback:       # the path does not follow the fit shown: said here, not only in the report view
            self.result.setText(f"Wrote {os.path.basename(path)}, but {in_our_terms(rep['warnings'][0])}. Close the "
                                f"panel, or change the settings and write again.")
            self.form.adjustSize()          # the whole message, not the label's first lines
        return True

    def accept(self):
        if not self.write() or self.fallback:       # (written, with a fallback: open, saying so)
            return False
        self._close()
        return True

    def reject(self):
        self._close()
        return True

    def _close(self):
        global ACTIVE
        import FreeCADGui
        FreeCADGui.Control.closeDialog()
        ACTIVE = None

    def getStandardButtons(self):
        return standard_buttons("Ok", "Cancel")


def wrote_text(path: str, rep) -> str:
    """What the panel and the report view say after writing: the file, and the cut's figures where the export
    measured them (XYUV: what the wire sweeps against the face, within its bound; flank: the face's points against
    the tool swept through its moves, with the gouge tolerance), in the document's unit (workbench.units)."""
    from .units import length
    out = f"Wrote {os.path.basename(path)}"
    rep = rep or {}
    cut, env = rep.get("cut"), (rep.get("tool_envelope") or {}).get("cl_positions")
    swept, gouge = rep.get("swept_tool"), (rep.get("machine") or {}).get("positions", {}).get("gouge_tol")
    if cut:
        out += (f": the cut measured {length(cut['max'])} from the face, within its bound {length(cut['bound'])} "
                f"(the fit's {length(rep.get('fit', {}).get('error_bound', 0.0))})")
    elif swept:
        over = (rep.get("overcut") or {}).get("larger", swept["overcut"])     # (the larger of the two measures)
        out += (f": the tool swept through its moves overcuts the face by {length(over)}"
                f"{f' (gouge tolerance {length(gouge)})' if gouge is not None else ''} and leaves "
                f"{length(swept['undercut'])}; its axis turns at most {swept['axis_angle_max_deg']:.2g} deg a move")
    elif env:
        out += f": the tool's overcut {length(env['overcut'])}, undercut {length(env['undercut'])} at its positions"
    return out + "."


# the defaults of new fits (Edit > Preferences > Ruled), read by features.fit_defaults
FIT_DEFAULTS = [("Samples", 40, "Samples per side", "samples per side of a new fit"),
                ("MeasureSamples", 40, "Measure samples", "n x n samples of a new fit's measured Hausdorff distance "
                 "(0: none)")]


class PreferencesPage:
    """Edit > Preferences > Ruled: the defaults of new fits and the export settings."""

    def __init__(self, parent=None):
        self.form = QtGui.QWidget(parent)
        self.form.setWindowTitle("Ruled")
        outer = QtGui.QVBoxLayout(self.form)
        fits = QtGui.QGroupBox("New fits")
        lay = QtGui.QFormLayout(fits)
        self.fit = {}
        for name, default, label, tip in FIT_DEFAULTS:
            w = QtGui.QSpinBox()
            w.setRange(0 if name == "MeasureSamples" else 3, 2000)
            w.setToolTip(tip)
            lay.addRow(label, w)
            self.fit[name] = w
        exp = QtGui.QGroupBox("Export for machining (also remembered from the export panel)")
        self.widgets = settings_rows(QtGui.QFormLayout(exp))
        outer.addWidget(fits)
        outer.addWidget(exp)
        outer.addStretch(1)

    def loadSettings(self):
        g = _group(FIT_GROUP)
        for name, default, *_ in FIT_DEFAULTS:
            self.fit[name].setValue(g.GetInt(name, default))
        v = load_settings()
        for name, w in self.widgets.items():
            _put(w, v[name])

    def saveSettings(self):
        g = _group(FIT_GROUP)
        for name, w in self.fit.items():
            g.SetInt(name, int(w.value()))
        save_settings({name: _get(w) for name, w in self.widgets.items()})
