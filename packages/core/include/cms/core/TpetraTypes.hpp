// Tpetra type aliases used across the layers, from the light forward
// declarations only: the heavy Tpetra headers stay in .cpp files.
#pragma once

#include <Teuchos_RCP.hpp>
#include <Tpetra_CrsMatrix_fwd.hpp>
#include <Tpetra_Map_fwd.hpp>
#include <Tpetra_MultiVector_fwd.hpp>
#include <Tpetra_Operator_fwd.hpp>
#include <Tpetra_Vector_fwd.hpp>

namespace cms {
using LocalOrdinal = ::Tpetra::Details::DefaultTypes::local_ordinal_type;
using GlobalOrdinal = ::Tpetra::Details::DefaultTypes::global_ordinal_type;
using Map = ::Tpetra::Map<>;
using CrsMatrix = ::Tpetra::CrsMatrix<double>;
using MultiVector = ::Tpetra::MultiVector<double>;
using Vector = ::Tpetra::Vector<double>;
using Operator = ::Tpetra::Operator<double>;
}  // namespace cms
