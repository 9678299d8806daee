"""A rigid body on a spring in one DOF, as a co-simulation FMU built with pythonfmu:

    mass * dv/dt = force - stiffness * position

`force` is an input (the water's force, from the hydrofmu FMU), `velocity` and `position`
are outputs. Over a step the input is held, and the motion is integrated exactly. Build it
with `pythonfmu build -f spring_body.py` (SpringBody.fmu, modelName SpringBody); its OSP
model description is SpringBody_OspModelDescription.xml beside this file.
"""
import math

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class SpringBody(Fmi2Slave):
    author = "hydrofmu"
    description = "Rigid body on a spring: mass dv/dt = force - stiffness position"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.mass = 1.0
        self.stiffness = 1.0
        self.position_start = 0.0
        self.force = 0.0
        self.position = 0.0
        self.velocity = 0.0
        for name in ("mass", "stiffness", "position_start"):
            self.register_variable(
                Real(name, causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed)
            )
        self.register_variable(Real("force", causality=Fmi2Causality.input))
        self.register_variable(Real("position", causality=Fmi2Causality.output))
        self.register_variable(Real("velocity", causality=Fmi2Causality.output))

    def exit_initialization_mode(self):
        self.position = self.position_start
        self.velocity = 0.0

    def do_step(self, current_time, step_size):
        w = math.sqrt(self.stiffness / self.mass)
        rest = self.force / self.stiffness
        c, s = math.cos(w * step_size), math.sin(w * step_size)
        x, v = self.position - rest, self.velocity
        self.position = rest + x * c + v / w * s
        self.velocity = -x * w * s + v * c
        return True
