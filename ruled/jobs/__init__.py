"""The job layer: the whole job of a face (read, fit, build, measure, write), of a wall, and of what is made
from a face's result (its machine data, its cone spline), each one function that every front door calls.

It sits above ``ruled.occ`` (it reads, builds and measures faces with OCCT) and below the front doors
(``ruled.cli``, ``ruled.cq``, ``ruled.batch``): the doors parse their inputs, call a job and present its
result; a job never imports a door.  What a face's job returns (``ruled.jobs.face.FaceFit``: the fit whose
figures agree, its built face, certified bound and measure) is what the machine and cone jobs take, so that
what the machine cuts is the fit the user saw.
"""
