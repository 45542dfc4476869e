#pragma once
// Whether this process writes the output files (report.json, gradcheck.json, .vtu, images,
// checkpoints) of the static and inverse verbs. A program that runs the same computation on
// every MPI rank (the replicated design of docs/petsc.md; bin/tailor with PETSc) sets it to
// false on all ranks but 0, so that one process writes each file. Default true.
namespace tailor {

void set_writes_output(bool writes);
bool writes_output();

}  // namespace tailor
