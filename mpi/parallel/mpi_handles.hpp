// RAII owners for MPI: the session, user operations and derived datatypes
// (the work queue owns its one-sided window). MPI's default error handler
// aborts, so no return code needs checking.
#pragma once

#include <mpi.h>

namespace treedyn::parallel {

class Session {
 public:
  Session(int* argc, char*** argv) {
    MPI_Init(argc, argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~Session() { MPI_Finalize(); }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
};

class Datatype {
 public:
  explicit Datatype(MPI_Datatype t) : type_(t) { MPI_Type_commit(&type_); }
  ~Datatype() { MPI_Type_free(&type_); }
  Datatype(const Datatype&) = delete;
  Datatype& operator=(const Datatype&) = delete;
  operator MPI_Datatype() const { return type_; }

 private:
  MPI_Datatype type_;
};

class Op {
 public:
  Op(MPI_User_function* f, bool commutative) { MPI_Op_create(f, commutative ? 1 : 0, &op_); }
  ~Op() { MPI_Op_free(&op_); }
  Op(const Op&) = delete;
  Op& operator=(const Op&) = delete;
  operator MPI_Op() const { return op_; }

 private:
  MPI_Op op_ = MPI_OP_NULL;
};

}  // namespace treedyn::parallel
