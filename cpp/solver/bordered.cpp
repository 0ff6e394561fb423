#include "solver/bordered.h"

#include <algorithm>

#include <mpi.h>

namespace nct::solver
{

namespace la = dolfinx::la;

System bordered(Monolithic& U, Border* border, const la::Vector<double>& first,
                std::function<void(la::Vector<double>&)> residual,
                std::function<void(Mat)> jacobian, double* matrix_time)
{
  static std::vector<double> none;
  System s;
  s.x = &U.x();
  s.y = border ? border->unknowns() : &none;
  s.residual = [&U, border, residual](la::Vector<double>& b, std::vector<double>& g)
  {
    U.unpack();
    if (border)
      border->apply();
    residual(b);
    if (border)
      border->constraints(g);
  };
  s.jacobian = [&U, border, jacobian, matrix_time](Mat A)
  {
    U.unpack();
    if (border)
      border->apply();
    MatZeroEntries(A);
    jacobian(A);
    const double t = MPI_Wtime();
    MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY); // off-process entries move here
    MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY);
    if (matrix_time)
      *matrix_time += MPI_Wtime() - t;
  };
  if (border)
    s.border = [&U, border, &first](std::vector<la::Vector<double>>& B,
                                    std::vector<la::Vector<double>>& C, std::vector<double>& D)
    {
      std::vector<la::Vector<double>> Bs(B.size(), first), Cs(C.size(), first);
      border->border(Bs, Cs, D);
      for (std::size_t i = 0; i < B.size(); ++i)
      {
        std::fill(B[i].mutable_array().begin(), B[i].mutable_array().end(), 0.0);
        std::fill(C[i].mutable_array().begin(), C[i].mutable_array().end(), 0.0);
        U.insert(0, Bs[i].array(), B[i]);
        U.insert(0, Cs[i].array(), C[i]);
      }
    };
  return s;
}

} // namespace nct::solver
