// kernel_violations.hpp — fixture for scripts/check_kernel_portability (never compiled): every line
// that the lint must flag says so in an `expect:` comment; every other line must pass. Lines marked
// "fine" are the look-alikes that must not be flagged.
#pragma once

#include <Kokkos_Core.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace fixture {

using namespace std;  // expect: using-namespace-std

template <class ExecSpace>
class Violations {
 public:
  Violations(Kokkos::View<double*, ExecSpace> v) : v_(v), scale_{2.0}, weights_(2, {1.0}) {
    auto w = v_;
    Kokkos::parallel_for(10, KOKKOS_LAMBDA(int i) { w(i) = 0; });  // expect: lambda-in-constructor
  }

  // fine: public, members copied into locals, device-safe calls, host code around the kernel.
  void fine(int n) {
    const auto v = v_;
    const double scale = scale_;
    const std::string label = "fixture::fine";
    std::vector<int> host_only(3, 0);
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const std::size_t k = static_cast<std::size_t>(i);
          v(k) = Kokkos::Experimental::sqrt(scale * v(k));
          if (v(k) < 0) Kokkos::abort("negative");
        });
    Kokkos::parallel_for(
        Kokkos::TeamPolicy<ExecSpace>(n, Kokkos::AUTO), KOKKOS_LAMBDA(const typename Kokkos::TeamPolicy<ExecSpace>::member_type& t) {
          Kokkos::parallel_for(Kokkos::TeamThreadRange(t, 4), [&](int j) { v(j) += 1; });
        });
    Kokkos::deep_copy(v, 1.0);
    Kokkos::parallel_for(Kokkos::RangePolicy<Kokkos::DefaultHostExecutionSpace>(0, n), [&](int i) { host_only[0] += i; });
  }

  void member_in_lambda(int n) {
    const auto v = v_;
    Kokkos::parallel_for(n, KOKKOS_LAMBDA(int i) {
      v(i) *= scale_;  // expect: lambda-captures-this
    });
  }

  void host_in_device(int n) {
    const auto v = v_;
    Kokkos::parallel_for(n, KOKKOS_LAMBDA(int i) {
      v(i) = std::sqrt(v(i));  // expect: std-in-device
      if (v(i) > 1) throw 1;  // expect: host-only-in-device
      printf("%d\n", i);  // expect: host-only-in-device
      long double wide = v(i);  // expect: long-double
      Kokkos::fence();  // expect: host-api-in-device
      Kokkos::parallel_for(3, KOKKOS_LAMBDA(int j) { v(j) = 0; });  // expect: dispatch-in-device, lambda-nested
      static int calls = 0;  // expect: static-in-device
      v(i) += wide + calls;
    });
    Kokkos::parallel_for(n, [=](int i) { v(i) = 1; });  // expect: plain-lambda-dispatch
  }

  void explicit_this(int n) {
    Kokkos::parallel_for(n, KOKKOS_LAMBDA(int i) { this->v_(i) = 0; });  // expect: this-in-lambda
  }

  auto deduced(int n) {
    const auto v = v_;
    Kokkos::parallel_for(n, KOKKOS_LAMBDA(int i) { v(i) = 0; });  // expect: lambda-deduced-return
    return n;
  }

  void generic(int n) {
    const auto v = v_;
    auto run = [&](auto count) {
      Kokkos::parallel_for(count, KOKKOS_LAMBDA(int i) { v(i) = 0; });  // expect: lambda-nested
    };
    run(n);
  }

  void uses_private_type(int n) {
    const Pair p{v_, scale_};
    Kokkos::parallel_for(n, KOKKOS_LAMBDA(int i) { p.v(i) = p.s; });  // expect: lambda-private-type
  }

  template <bool Flag>
  void constexpr_if(int n, double h) {
    const auto v = v_;
    Kokkos::parallel_for(n, KOKKOS_LAMBDA(int i) {
      if constexpr (Flag) v(i) = h;  // expect: lambda-capture-in-if-constexpr
    });
    Kokkos::parallel_for(n, KOKKOS_LAMBDA(int i) {
      if constexpr (Flag)
        for (int d = 0; d < 2; ++d) v(i) += d;  // expect: lambda-capture-in-if-constexpr
    });
    // fine: both captured before the `if constexpr`, locals of the lambda inside it.
    Kokkos::parallel_for(n, KOKKOS_LAMBDA(int i) {
      const double scale = h;
      v(i) = 0;
      if constexpr (Flag) {
        for (int d = 0; d < 2; ++d) v(i) += scale * d;
      }
    });
  }

  KOKKOS_INLINE_FUNCTION double device_member(double x) const {
    return std::max(x, scale_);  // expect: std-in-device
  }

 private:
  struct Pair {
    Kokkos::View<double*, ExecSpace> v;
    double s;
  };

  void hidden(int n) {
    const auto v = v_;
    Kokkos::parallel_for(n, KOKKOS_LAMBDA(int i) { v(i) = 0; });  // expect: lambda-in-private
  }

  Kokkos::View<double*, ExecSpace> v_;
  double scale_;
  std::vector<double> weights_;
};

// fine: a free function with host-only code outside its kernel.
template <class ExecSpace>
double free_function(const Kokkos::View<double*, ExecSpace>& v) {
  if (v.extent(0) == 0) throw std::invalid_argument("empty: " + std::to_string(v.extent(0)));
  double sum = 0;
  Kokkos::parallel_reduce(
      v.extent(0), KOKKOS_LAMBDA(int i, double& acc) { acc += v(i); }, sum);
  return std::sqrt(sum);
}

void local_class(Kokkos::View<double*> v) {
  struct Local {
    Kokkos::View<double*> w;
    void run() {
      auto w_ = w;
      Kokkos::parallel_for(1, KOKKOS_LAMBDA(int i) { w_(i) = 0; });  // expect: lambda-local-class
    }
  };
  Local{v}.run();
}

// A callback's type is a template argument of the function around the kernel.
template <class ExecSpace, class Callback>
double with_callback(Kokkos::View<double*, ExecSpace> v, Callback&& callback) {
  Kokkos::parallel_for(v.extent(0), KOKKOS_LAMBDA(int i) { v(i) = 0; });  // expect: lambda-host-callback
  return callback();
}

// fine: a functor-like argument used only inside the kernel (a KOKKOS_LAMBDA closure from the caller).
template <class ExecSpace, class Body>
void with_body(Kokkos::View<double*, ExecSpace> v, const Body& body) {
  Kokkos::parallel_for(v.extent(0), KOKKOS_LAMBDA(int i) { v(i) = body(i); });
}

// GoogleTest makes a TEST body the private TestBody() of a generated class.
TEST(Fixture, KernelInTestBody) {
  Kokkos::View<double*> v("v", 1);
  Kokkos::parallel_for(1, KOKKOS_LAMBDA(int i) { v(i) = 1; });  // expect: lambda-in-private
}

}  // namespace fixture
