"""Static checks of every shipped FMU: fmpy's validator and the 34 exported fmi2 functions."""
import subprocess
import tempfile
import zipfile

from fmpy.validation import validate_fmu

FMI2_FUNCTIONS = """
fmi2GetTypesPlatform fmi2GetVersion fmi2SetDebugLogging fmi2Instantiate fmi2FreeInstance
fmi2SetupExperiment fmi2EnterInitializationMode fmi2ExitInitializationMode fmi2Terminate fmi2Reset
fmi2GetReal fmi2GetInteger fmi2GetBoolean fmi2GetString fmi2SetReal fmi2SetInteger fmi2SetBoolean
fmi2SetString fmi2GetFMUstate fmi2SetFMUstate fmi2FreeFMUstate fmi2SerializedFMUstateSize
fmi2SerializeFMUstate fmi2DeSerializeFMUstate fmi2GetDirectionalDerivative
fmi2SetRealInputDerivatives fmi2GetRealOutputDerivatives fmi2DoStep fmi2CancelStep fmi2GetStatus
fmi2GetRealStatus fmi2GetIntegerStatus fmi2GetBooleanStatus fmi2GetStringStatus
""".split()


def test_fmpy_validate_reports_no_problem(fmus):
    for name, path in fmus.items():
        assert validate_fmu(path) == [], name


def test_all_34_functions_are_exported(fmus):
    assert len(FMI2_FUNCTIONS) == 34
    for name, path in fmus.items():
        with zipfile.ZipFile(path) as z, tempfile.TemporaryDirectory() as d:
            so = z.extract(f"binaries/linux64/{name}.so", d)
            out = subprocess.run(["nm", "-D", "--defined-only", so], capture_output=True, text=True, check=True).stdout
        exported = {line.split()[-1] for line in out.splitlines() if line.strip()}
        missing = [f for f in FMI2_FUNCTIONS if f not in exported]
        assert not missing, f"{name}: missing {missing}"


def test_fmu_layout(fmus):
    for name, path in fmus.items():
        with zipfile.ZipFile(path) as z:
            names = set(z.namelist())
        assert {"modelDescription.xml", "resources/scene.toml", f"binaries/linux64/{name}.so"} <= names
