#!/usr/bin/env python3
"""OpenSim 4.6's ProbeReporter of Umberger2010 and Bhargava2004 MuscleMetabolicsProbes in an
AnalyzeTool, and its actuator force and power probes: arm26 with nine probes (fixtures/models/arm26_probes.osim, written here) from the states of OpenSim's forward
simulation of arm26 (the `states` AnalyzeTool golden's), the muscles excited by a setup
PrescribedController (sines about their activations, so that excitation is above activation in
some rows and below in others):

* `metabolics`: every muscle (slow-twitch ratios 0.3–0.8), OpenSim's defaults otherwise, per
  muscle and basal rates reported;
* `tuned`: three muscles (one with a provided mass), the Bhargava recruitment model, negative
  mechanical work, the minimum heat rate and the non-negative total off, aerobic factor 1.2,
  basal exponent 0.8, effort scaling 0.9, gain 2, the total only;
* `idle`: disabled (ProbeReporter skips it);
* `bhargava`: a Bhargava2004MuscleMetabolicsProbe of every muscle (BRA with its own twitch
  constants), OpenSim's defaults otherwise, per muscle and basal rates reported;
* `bhargava_tuned`: two muscles (one with a provided mass), the force-dependent shortening
  constant, another fiber-length dependence of the maintenance rate, negative mechanical work, the
  minimum heat rate and the non-negative total off, the maintenance rate off, basal coefficient
  1.1, effort scaling 1.1, the total only;
* `forces`: an ActuatorForceProbe of all actuators; `forces_squared`: of three, squared and
  summed; `powers`: an ActuatorPowerProbe of two; `powers_cubed`: of all, cubed and summed
  (OpenSim 4.6 cannot read a MuscleActiveFiberPowerProbe from a file: it is not registered).

Writes fixtures/golden/analyze_tool/probes/ (the AnalyzeTool tests run it with the other cases):
setup.xml, files.txt and every table.

    python3 oracle/gen_probes.py
"""
from pathlib import Path

import opensim as osim
from gen_analyze_tool import OUT, run_setup

REPO = Path(__file__).resolve().parent.parent
MUSCLES = ["TRIlong", "TRIlat", "TRImed", "BIClong", "BICshort", "BRA"]
EXCITATIONS = "".join(f"<Sine><amplitude>0.3</amplitude><omega>{15 + 4 * k}</omega><phase>{0.5 * k}</phase><offset>0.2</offset></Sine>" for k in range(len(MUSCLES)))
SETUP = f"""<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
\t<AnalyzeTool name="walk">
\t\t<model_file>arm26_probes.osim</model_file>
\t\t<results_directory>Results</results_directory>
\t\t<initial_time>0.05</initial_time>
\t\t<final_time>0.25</final_time>
\t\t<AnalysisSet name="Analyses">
\t\t\t<objects>
\t\t\t\t<ProbeReporter name="ProbeReporter"><on>true</on><step_interval>2</step_interval></ProbeReporter>
\t\t\t</objects>
\t\t</AnalysisSet>
\t\t<ControllerSet name="Controllers"><objects><PrescribedController name="excite"><actuator_list>{" ".join(MUSCLES)}</actuator_list><FunctionSet name="ControlFunctions"><objects>{EXCITATIONS}</objects></FunctionSet></PrescribedController></objects></ControllerSet>
\t\t<states_file>arm26_states.sto</states_file>
\t\t<lowpass_cutoff_frequency_for_coordinates>-1</lowpass_cutoff_frequency_for_coordinates>
\t</AnalyzeTool>
</OpenSimDocument>
"""


def probe_model():
    """arm26 with the three probes, as OpenSim prints it."""
    model = osim.Model(str(REPO / "fixtures" / "models" / "arm26.osim"))
    metabolics = osim.Umberger2010MuscleMetabolicsProbe(True, True, True, True)
    metabolics.setName("metabolics")
    metabolics.set_report_total_metabolics_only(False)
    for k, muscle in enumerate(MUSCLES):
        metabolics.addMuscle(muscle, 0.3 + 0.1 * k)
    model.addProbe(metabolics)
    tuned = osim.Umberger2010MuscleMetabolicsProbe(True, True, True, True)
    tuned.setName("tuned")
    for name, value in [("use_Bhargava_recruitment_model", False), ("include_negative_mechanical_work", False), ("enforce_minimum_heat_rate_per_muscle", False),
                        ("forbid_negative_total_power", False), ("aerobic_factor", 1.2), ("basal_exponent", 0.8), ("muscle_effort_scaling_factor", 0.9), ("gain", 2.0)]:
        getattr(tuned, f"set_{name}")(value)
    tuned.addMuscle("TRIlong", 0.5)
    tuned.addMuscle("BIClong", 0.6, 0.25)
    tuned.addMuscle("BRA", 0.4)
    model.addProbe(tuned)
    idle = osim.Umberger2010MuscleMetabolicsProbe(True, True, True, True)
    idle.setName("idle")
    idle.addMuscle("BRA", 0.5)
    idle.set_enabled(False)
    model.addProbe(idle)
    bhargava = osim.Bhargava2004MuscleMetabolicsProbe(True, True, True, True, True)
    bhargava.setName("bhargava")
    bhargava.set_report_total_metabolics_only(False)
    for k, muscle in enumerate(MUSCLES[:-1]):
        bhargava.addMuscle(muscle, 0.3 + 0.1 * k, 40.0, 133.0, 74.0, 111.0)
    bhargava.addMuscle("BRA", 0.6, 35.0, 120.0, 80.0, 100.0)
    model.addProbe(bhargava)
    tuned = osim.Bhargava2004MuscleMetabolicsProbe(True, False, True, True, True)
    tuned.setName("bhargava_tuned")
    for name, value in [("use_force_dependent_shortening_prop_constant", True), ("include_negative_mechanical_work", False), ("enforce_minimum_heat_rate_per_muscle", False),
                        ("forbid_negative_total_power", False), ("basal_coefficient", 1.1), ("muscle_effort_scaling_factor", 1.1)]:
        getattr(tuned, f"set_{name}")(value)
    curve = osim.PiecewiseLinearFunction()
    for x, y in [(0.0, 0.4), (0.8, 0.6), (1.2, 1.0), (2.0, 0.2)]:
        curve.addPoint(x, y)
    tuned.set_normalized_fiber_length_dependence_on_maintenance_rate(curve)
    tuned.addMuscle("TRIlat", 0.5, 40.0, 133.0, 74.0, 111.0)
    tuned.addMuscle("BICshort", 0.4, 40.0, 133.0, 74.0, 111.0, 0.3)
    model.addProbe(tuned)
    for probe, name, actuators, summed, exponent in [(osim.ActuatorForceProbe, "forces", ["all"], False, 1.0), (osim.ActuatorForceProbe, "forces_squared", ["TRIlong", "BIClong", "BRA"], True, 2.0),
                                                     (osim.ActuatorPowerProbe, "powers", ["TRIlat", "BICshort"], False, 1.0), (osim.ActuatorPowerProbe, "powers_cubed", ["ALL"], True, 3.0)]:
        names = osim.ArrayStr()
        for actuator in actuators:
            names.append(actuator)
        added = probe(names, summed, exponent)
        added.setName(name)
        model.addProbe(added)
    model.finalizeConnections()
    file = REPO / "fixtures" / "models" / "arm26_probes.osim"
    model.printToXML(str(file))
    # OpenSim prints `all` spelled out; the file keeps it, as a lab writes it.
    text = file.read_text()
    spelled = '<ActuatorForceProbe name="forces">'
    at = text.index(spelled)
    listed = "<actuator_names>TRIlong TRIlat TRImed BIClong BICshort BRA</actuator_names>"
    file.write_text(text[:at] + text[at:].replace(listed, "<actuator_names>all</actuator_names>", 1))


def main():
    osim.Logger.setLevelString("error")
    probe_model()
    out = OUT / "probes"
    out.mkdir(parents=True, exist_ok=True)
    (out / "setup.xml").write_text(SETUP)
    run_setup(out, lambda name: True)
    print("probes written", sorted(p.name for p in out.iterdir()))


if __name__ == "__main__":
    main()
