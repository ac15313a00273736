// SPDX-License-Identifier: BSD-3-Clause
#include "vtkAdaptToShocks.h"

#include "vtkARMeshKernels.h"
#include "vtkARParallel.h"
#include "vtkAppendPolyData.h"
#include "ARSurfaceFit.h"
#include "ARSurfaceRemesh.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellDataToPointData.h"
#include "vtkCellTypes.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkDummyController.h"
#include "vtkEmbeddedRemesh.h"
#include "vtkFeatureCluster.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkQuadricFit.h"
#include "vtkShockSensor.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <iterator>
#include <array>
#include <limits>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkAdaptToShocks);

namespace
{
// Two shocks meet in a cluster when its nodes' shock normals form two tight
// families clearly apart (ar::SplitDirectionFamilies): the families' axes
// at least MeetingAngle degrees and MeetingSeparation times the families'
// median spread apart, the lighter family at least MeetingFraction of the
// weight. One family split in two (a plane shock) gives axes a few degrees
// apart; a continuous family (a cone, a curved shock) axes at most about 4
// times the spread apart: 8 is twice that bound.
constexpr double MeetingAngle = 10.0;
constexpr double MeetingSeparation = 8.0;
constexpr double MeetingFraction = 0.1;

/**
 * The shock normals of the chosen clusters: at each node of a chosen
 * cluster, the gradient of the sensor's pressure (or, with the conserved
 * variables, its density), averaged from the cells around the node (ghost
 * cells complete the stencils at partition boundaries), weighted by its
 * magnitude; split into two families per cluster on rank 0. Returns the
 * message for the first cluster in which two shocks meet, else "";
 * `families` gets each cluster's angle, spread and fraction (NaN: not
 * computed). Collective.
 */
std::string TwoShocksMeet(vtkUnstructuredGrid* mesh, const std::vector<int>& chosen, const std::vector<double>& sizes,
  std::vector<double>& families)
{
  families.assign(3 * chosen.size(), std::numeric_limits<double>::quiet_NaN());
  const bool root = vtkARParallel::Rank() == 0;
  auto* flow = vtkStringArray::SafeDownCast(mesh->GetFieldData()->GetAbstractArray("FlowStateArrays"));
  vtkIntArray* ids = vtkIntArray::SafeDownCast(mesh->GetPointData()->GetArray("ClusterId"));
  std::string name = flow && flow->GetNumberOfValues() > 1 ? flow->GetValue(1) : "";
  vtkSmartPointer<vtkDataArray> jump = mesh->GetPointData()->GetArray(name.c_str());
  if (!jump && mesh->GetCellData()->GetArray(name.c_str()))
  {
    vtkNew<vtkUnstructuredGrid> cells; // a cell field: averaged to the points
    cells->CopyStructure(mesh);
    cells->GetCellData()->AddArray(mesh->GetCellData()->GetArray(name.c_str()));
    vtkNew<vtkCellDataToPointData> toPoints;
    toPoints->SetInputData(cells);
    toPoints->Update();
    jump = toPoints->GetOutput()->GetPointData()->GetArray(name.c_str());
  }
  vtkARMeshKernels::MeshView view;
  std::string error;
  double usable = jump && ids && jump->GetNumberOfComponents() == 1 && view.Build(mesh, error) ? 1.0 : 0.0;
  if (usable == 0.0)
  {
    view = vtkARMeshKernels::MeshView();
  }
  std::vector<int> slot(usable > 0.0 ? mesh->GetNumberOfPoints() : 0, -1);
  for (std::size_t j = 0; j < chosen.size(); ++j)
  {
    for (vtkIdType p = 0; p < static_cast<vtkIdType>(slot.size()); ++p)
    {
      if (ids->GetValue(p) == chosen[j])
      {
        slot[p] = static_cast<int>(j);
      }
    }
  }
  std::vector<double> gradient;
  if (usable > 0.0)
  {
    vtkARMeshKernels::CellsToPoints(
      view, 3,
      [&](vtkIdType c, double* g, double& weight) {
        const vtkIdType* pts = view.CellPoints(c);
        const int n = view.CellSize(c);
        bool near = false;
        for (int a = 0; a < n && !near; ++a)
        {
          near = slot[pts[a]] >= 0;
        }
        double W[vtkARMeshKernels::MaxCellPoints][3];
        int m;
        if (!near || !view.IsVolumeCell(c) || !vtkARMeshKernels::GradientOperator(view, c, W, m, weight))
        {
          return false;
        }
        g[0] = g[1] = g[2] = 0.0;
        for (int a = 0; a < m; ++a)
        {
          const double q = jump->GetComponent(pts[a], 0);
          for (int k = 0; k < 3; ++k)
          {
            g[k] += W[a][k] * q;
          }
        }
        return true;
      },
      gradient, nullptr);
  }
  for (std::size_t j = 0; j < chosen.size(); ++j)
  {
    std::vector<double> local; // gx gy gz |g| per owned node of the cluster
    for (vtkIdType p = 0; p < static_cast<vtkIdType>(slot.size()); ++p)
    {
      if (slot[p] == static_cast<int>(j) && view.IsOwnedPoint(p))
      {
        const double* g = &gradient[3 * p];
        local.insert(local.end(), { g[0], g[1], g[2], std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) });
      }
    }
    const std::vector<double> all = vtkARParallel::GatherOnRoot(local);
    // [meet, angle, spread, fraction, axis 0, axis 1]: rank 0's, summed.
    double verdict[10] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };
    const std::size_t n = all.size() / 4;
    if (root)
    {
      // NaN (summed: NaN everywhere) unless computed below
      verdict[1] = verdict[2] = verdict[3] = std::numeric_limits<double>::quiet_NaN();
    }
    if (n >= 2)
    {
      std::vector<double> directions(3 * n), weights(n);
      for (std::size_t i = 0; i < n; ++i)
      {
        std::copy(&all[4 * i], &all[4 * i + 3], &directions[3 * i]);
        weights[i] = all[4 * i + 3];
      }
      ar::DirectionFamilies families;
      if (ar::SplitDirectionFamilies(directions.data(), weights.data(), n, families))
      {
        verdict[0] = families.AngleDegrees >= MeetingAngle &&
            families.AngleDegrees >= MeetingSeparation * families.SpreadDegrees &&
            families.Fraction >= MeetingFraction
          ? 1.0
          : 0.0;
        verdict[1] = families.AngleDegrees;
        verdict[2] = families.SpreadDegrees;
        verdict[3] = families.Fraction;
        std::copy(families.Axes[0], families.Axes[0] + 3, verdict + 4);
        std::copy(families.Axes[1], families.Axes[1] + 3, verdict + 7);
      }
    }
    vtkARParallel::AllReduceSum(verdict, 10);
    std::copy(verdict + 1, verdict + 4, &families[3 * j]);
    if (verdict[0] > 0.0)
    {
      std::ostringstream msg;
      msg.precision(3);
      msg << "two shocks meet in cluster " << chosen[j] << " (" << static_cast<long long>(sizes[chosen[j]])
          << " nodes): the shock normals at its nodes (the gradient of " << name
          << ") form two families " << verdict[1] << " degrees apart, each within " << verdict[2]
          << " degrees (median) of its own direction, (" << verdict[4] << ", " << verdict[5] << ", "
          << verdict[6] << ") and (" << verdict[7] << ", " << verdict[8] << ", " << verdict[9]
          << "), the smaller holding " << 100.0 * verdict[3]
          << "% of the cluster. No single plane, cone or quadric follows both, and surfaces that "
             "meet cannot be embedded together: to adapt to one of them, fit it by hand "
             "(QuadricFit on the medial points on its side of the line where they meet) and "
             "remesh with EmbeddedRemesh.";
      return msg.str();
    }
  }
  return std::string();
}
}


//------------------------------------------------------------------------------
vtkAdaptToShocks::vtkAdaptToShocks()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
void vtkAdaptToShocks::SetClusterTemplate(int cluster, int templ)
{
  auto it = this->ClusterTemplates.find(cluster);
  if (it == this->ClusterTemplates.end() || it->second != templ)
  {
    this->ClusterTemplates[cluster] = templ;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkAdaptToShocks::ClearClusterTemplates()
{
  if (!this->ClusterTemplates.empty())
  {
    this->ClusterTemplates.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkAdaptToShocks::FillInputPortInformation(int, vtkInformation* info)
{
  info->Remove(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE());
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkMultiBlockDataSet");
  return 1;
}

//------------------------------------------------------------------------------
int vtkAdaptToShocks::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkDataObject" : "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkAdaptToShocks::RequestDataObject(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return vtkEmbeddedRemesh::MeshAndSurfaceDataObjects(inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkAdaptToShocks::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Threads for this filter's own work only: the process's SMP backend is
  // left as the user has it.
  int result = 1;
  vtkARMeshKernels::Threaded([&]() { result = this->ExecuteData(request, inputVector, outputVector); });
  return result;
}

//------------------------------------------------------------------------------
namespace
{
/**
 * AdaptToShocks' run: the stages of vtkAdaptToShocks::ExecuteData over the
 * state they share (as Remesh2DRun in vtkEmbeddedRemesh2D.cxx; file-local,
 * so its members keep the names the stages had as locals). Every rank runs
 * every stage (each has collective calls), and every rank decides the same.
 * A stage returns false when the run ends there: after PassThrough (an
 * error, the input passed through) or when cancelled.
 */
class AdaptRun
{
public:
  AdaptRun(vtkAdaptToShocks* self_, const std::map<int, int>& clusterTemplates_, vtkDataObject* input_,
    vtkDataObject* output_, vtkPolyData* surfaces_)
    : self(self_)
    , clusterTemplates(clusterTemplates_)
    , input(input_)
    , output(output_)
    , surfaces(surfaces_)
    , start(std::chrono::steady_clock::now())
  {
  }
  bool Check();        ///< the properties EmbeddedRemesh or FeatureCluster would clamp; the volume
  bool Sense();        ///< 1. the shock sensor
  bool Cluster();      ///< 2. the clusters of the Mn = 1 band, those that get a surface
  bool FitEach();      ///< 3. one fitted surface per chosen cluster
  bool JoinPieces();   ///< the pieces of one shock joined into one surface
  void DropCrossing(); ///< a surface that crosses a larger cluster's left out
  void Append();       ///< the kept surfaces, numbered, in one polydata
  bool Remesh();       ///< 4. the remeshing with every surface embedded
  void Output();       ///< the outputs and their field data

private:
  bool PassThrough(const std::string& message);
  double Lap();
  vtkSmartPointer<vtkPolyData> FitClusters(
    const std::vector<int>& ks, std::string& templateName, std::array<double, 2>& measure);
  void GatherIfHybrid();
  double SurfacesShockThickness() const;

  vtkAdaptToShocks* self;
  const std::map<int, int>& clusterTemplates;
  vtkDataObject* input;
  vtkDataObject* output;
  vtkPolyData* surfaces;
  std::chrono::steady_clock::time_point start;
  double secondsSensor = 0.0, secondsClusters = 0.0, secondsFit = 0.0, secondsRemesh = 0.0;
  // Check, Sense, Cluster
  vtkUnstructuredGrid* volume = nullptr;
  vtkNew<vtkShockSensor> sensor;
  vtkUnstructuredGrid* sensed = nullptr;
  vtkNew<vtkFeatureCluster> clusters;
  std::vector<double> sizes;
  std::vector<int> chosen;
  std::vector<double> families;
  // FitEach, JoinPieces, DropCrossing, Append
  std::vector<vtkSmartPointer<vtkPolyData>> fitted;
  std::vector<std::vector<int>> fittedClusters; // the clusters of each fitted surface
  std::vector<std::string> fittedTemplate;      // its template's name
  std::vector<std::array<double, 2>> fittedMeasure; // its RMS residual and edge length
  vtkSmartPointer<vtkPolyData> domainBoundary;      // the volume's, for every fit (FitClusters)
  std::ostringstream fitProblems;
  vtkNew<vtkAppendPolyData> append;
  vtkNew<vtkStringArray> templates;
  vtkNew<vtkStringArray> members; // "0", or "0+2+1" for a shock joined from pieces
  // Remesh
  vtkMultiProcessController* ctrl = nullptr;
  bool root = true;
  vtkSmartPointer<vtkDataObject> remeshInput;
  bool alone = false;
  double shockThickness = 0.0;
};

//------------------------------------------------------------------------------
bool AdaptRun::PassThrough(const std::string& message)
{
  vtkErrorWithObjectMacro(self, << "AdaptToShocks: " << message << " The input passes through unchanged.");
  output->ShallowCopy(input);
  surfaces->Initialize();
  return false;
}

//------------------------------------------------------------------------------
double AdaptRun::Lap()
{
  const auto now = std::chrono::steady_clock::now();
  const double s = std::chrono::duration<double>(now - start).count();
  start = now;
  return s;
}

//------------------------------------------------------------------------------
bool AdaptRun::Check()
{
  // ---- Properties EmbeddedRemesh or FeatureCluster would clamp: refused here.
  std::ostringstream bad;
  const int mode = self->GetMode();
  const double removal = self->GetRemovalFactor();
  const double fraction = self->GetMinimumClusterFraction();
  if (mode != 0 && mode != 1)
  {
    bad << "Mode is " << mode << "; it must be 0 (LocalCavity) or 1 (FullDomain). ";
  }
  if (!(removal > 0.0) || !std::isfinite(removal) || removal > 1e3)
  {
    bad << "RemovalFactor is " << removal << "; it must lie in (0, 1000]. ";
  }
  if (self->GetMinimumClusterSize() < 1)
  {
    bad << "MinimumClusterSize is " << self->GetMinimumClusterSize() << "; it must be at least 1. ";
  }
  if (!(fraction > 0.0 && fraction <= 1.0))
  {
    bad << "MinimumClusterFraction is " << fraction << "; it must lie in (0, 1]. ";
  }
  if (self->GetMaximumNumberOfSurfaces() < 1)
  {
    bad << "MaximumNumberOfSurfaces is " << self->GetMaximumNumberOfSurfaces() << "; it must be at least 1. ";
  }
  for (const auto& ct : clusterTemplates)
  {
    if (ct.second < vtkQuadricFit::PLANE || ct.second > vtkQuadricFit::AUTOMATIC)
    {
      bad << "The template of cluster " << ct.first << " is " << ct.second
          << "; it must be 0 (Plane), 1 (Quadric), 2 (Cone), 3 (Quartic) or 4 (Automatic). ";
    }
  }
  if (!bad.str().empty())
  {
    return PassThrough(bad.str());
  }
  volume = vtkEmbeddedRemesh::VolumeLeaf(input);
  if (!volume || volume->GetNumberOfCells() == 0)
  {
    return PassThrough("The input has no volume mesh (an unstructured grid with 3-D cells, or a "
                       "multiblock with an internalMesh).");
  }
  return true;
}

//------------------------------------------------------------------------------
bool AdaptRun::Sense()
{
  // ---- 1. The shock sensor.
  sensor->SetInputData(volume);
  sensor->SetGamma(self->GetGamma());
  sensor->SetGasConstant(self->GetGasConstant());
  sensor->Update();
  sensed = sensor->GetOutput();
  if (!sensed->GetPointData()->GetArray("NormalMach"))
  {
    return PassThrough("the shock sensor could not run (see its message above).");
  }
  secondsSensor = Lap();
  return true;
}

//------------------------------------------------------------------------------
bool AdaptRun::Cluster()
{
  // ---- 2. The clusters of the Mn = 1 band.
  clusters->SetInputConnection(sensor->GetOutputPort());
  clusters->SetSensorRange(self->GetSensorRange());
  clusters->SetMinimumClusterSize(self->GetMinimumClusterSize());
  clusters->Update();
  auto* medial = vtkPolyData::SafeDownCast(clusters->GetOutputDataObject(1));
  // The cluster sizes are rank 0's (with the medial points): every rank
  // needs them, to choose the same clusters and take part in each fit.
  vtkDataArray* sizeArray = medial ? medial->GetFieldData()->GetArray("ClusterSizes") : nullptr;
  double header[2] = { sizeArray ? 1.0 : 0.0, sizeArray ? static_cast<double>(sizeArray->GetNumberOfTuples()) : 0.0 };
  header[0] = clusters->GetOutput()->GetPointData()->GetArray("FeatureMask") ? header[0] : -1.0;
  double missingMask = header[0] < 0.0 ? 1.0 : 0.0;
  vtkARParallel::AllReduceMax(header, 2);
  vtkARParallel::AllReduceMax(&missingMask, 1);
  sizes.assign(static_cast<std::size_t>(header[1]), 0.0);
  for (std::size_t k = 0; sizeArray && k < sizes.size(); ++k)
  {
    sizes[k] = sizeArray->GetComponent(static_cast<vtkIdType>(k), 0);
  }
  vtkARParallel::AllReduceSum(sizes.data(), static_cast<int>(sizes.size()));
  if (missingMask > 0.0 || header[0] <= 0.0)
  {
    return PassThrough("feature clustering could not run (see its message above).");
  }
  if (sizes.empty())
  {
    vtkDataArray* cells = sensed->GetCellData()->GetArray("ShockCells");
    double shockCells = 0.0;
    for (vtkIdType c = 0; cells && c < cells->GetNumberOfTuples(); ++c)
    {
      shockCells += cells->GetComponent(c, 0);
    }
    vtkARParallel::AllReduceSum(&shockCells, 1);
    std::ostringstream msg;
    msg << "No shock found: the shock sensor marks " << shockCells
        << " shock cells, and no cluster of at least MinimumClusterSize (" << self->GetMinimumClusterSize()
        << ") nodes has NormalMach in the sensor range.";
    return PassThrough(msg.str());
  }
  // The clusters that get a surface (ids are by decreasing size).
  const double largest = sizes[0];
  for (std::size_t k = 0; k < sizes.size() && static_cast<int>(chosen.size()) < self->GetMaximumNumberOfSurfaces(); ++k)
  {
    if (sizes[k] >= self->GetMinimumClusterFraction() * largest)
    {
      chosen.push_back(static_cast<int>(k));
    }
  }
  // Two shocks that meet (an X, a V, a lambda) in one cluster: no template
  // fits them, and the fit's residual alone does not show it.
  const std::string meeting = TwoShocksMeet(clusters->GetOutput(), chosen, sizes, families);
  if (!meeting.empty())
  {
    return PassThrough(meeting);
  }
  secondsClusters = Lap();
  return true;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkPolyData> AdaptRun::FitClusters(
  const std::vector<int>& ks, std::string& templateName, std::array<double, 2>& measure)
{
  // One QuadricFit of the clusters `ks` together; its surface (null if none)
  // and its template's name, RMS residual and edge length.
  vtkNew<vtkQuadricFit> fit;
  fit->SetInputConnection(clusters->GetOutputPort(1));
  fit->SetDomainData(volume);
  if (!domainBoundary)
  {
    // Once per run, for every fit (collective: every rank fits the same clusters).
    domainBoundary = vtkARParallel::GatherDomainBoundary(volume);
  }
  fit->SetDomainBoundary(domainBoundary);
  fit->SetClusterId(ks[0]);
  fit->SetExtraClusterIds(std::vector<int>(ks.begin() + 1, ks.end()));
  const auto named = clusterTemplates.find(ks[0]);
  fit->SetTemplate(named == clusterTemplates.end() ? vtkQuadricFit::AUTOMATIC : named->second);
  fit->SetGamma(self->GetGamma()); // the centring's Rankine-Hugoniot jump
  fit->Update();
  vtkPolyData* surface = fit->GetOutput();
  auto* name = vtkStringArray::SafeDownCast(surface->GetFieldData()->GetAbstractArray("Template"));
  vtkDataArray* rms = surface->GetFieldData()->GetArray("RMSResidual");
  vtkDataArray* edge = surface->GetFieldData()->GetArray("SurfaceEdgeLength");
  // (the surface is on rank 0 under MPI: every rank decides the same)
  const double lowest = -std::numeric_limits<double>::max();
  double have[3] = { name && surface->GetNumberOfCells() > 0 ? 1.0 : 0.0, rms ? rms->GetComponent(0, 0) : lowest,
    edge ? edge->GetComponent(0, 0) : lowest };
  vtkARParallel::AllReduceMax(have, 3);
  measure = { have[1], have[2] };
  templateName = name ? name->GetValue(0) : "";
  vtkSmartPointer<vtkPolyData> copy;
  if (have[0] > 0.0)
  {
    copy = vtkSmartPointer<vtkPolyData>::New();
    copy->ShallowCopy(surface);
  }
  return copy;
}

//------------------------------------------------------------------------------
bool AdaptRun::FitEach()
{
  // ---- 3. One fitted surface per chosen cluster, then the pieces of one
  // shock joined (JoinPieces): a captured shock often falls into several
  // clusters (where the band thins, or at a wall), and the centred fits of
  // its pieces lie on one surface, overlapping and a fraction of a cell
  // apart, which leaves slivers between them (9.7 degrees on wedge20Ma4tri's
  // three planes).
  for (const int k : chosen)
  {
    std::string name;
    std::array<double, 2> measure;
    vtkSmartPointer<vtkPolyData> surface = FitClusters({ k }, name, measure);
    if (!surface)
    {
      fitProblems << " cluster " << k << " (" << sizes[k] << " nodes)";
      continue;
    }
    fitted.push_back(surface);
    fittedClusters.push_back({ k });
    fittedTemplate.push_back(name);
    fittedMeasure.push_back(measure);
    if (self->CheckAbort())
    {
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
bool AdaptRun::JoinPieces()
{
  // Join two surfaces when one surface fits both clusters' points as well as
  // each alone: its RMS residual within the automatic template's bound of the
  // worse one (1.25 x + 0.1 of the edge length). Two different shocks (two
  // planes apart, a plane and a cone) leave a residual of their distance.
  // Clusters with a template of their own (ClusterTemplates) stay alone.
  auto own = [this](const std::vector<int>& ks) {
    return std::any_of(ks.begin(), ks.end(), [this](int k) { return this->clusterTemplates.count(k) > 0; });
  };
  for (std::size_t i = 0; i < fitted.size(); ++i)
  {
    for (std::size_t j = i + 1; j < fitted.size(); ++j)
    {
      if (own(fittedClusters[i]) || own(fittedClusters[j]))
      {
        continue;
      }
      std::vector<int> both = fittedClusters[i];
      both.insert(both.end(), fittedClusters[j].begin(), fittedClusters[j].end());
      std::string name;
      std::array<double, 2> measure;
      vtkSmartPointer<vtkPolyData> surface = FitClusters(both, name, measure);
      const double worse = std::max(fittedMeasure[i][0], fittedMeasure[j][0]);
      const double edge = std::max(fittedMeasure[i][1], fittedMeasure[j][1]);
      if (surface && measure[0] <= ar::AutomaticTemplateRatio * worse + ar::AutomaticTemplateSlack * edge)
      {
        fitted[i] = surface;
        fittedClusters[i] = both;
        fittedTemplate[i] = name;
        fittedMeasure[i] = measure;
        fitted.erase(fitted.begin() + j);
        fittedClusters.erase(fittedClusters.begin() + j);
        fittedTemplate.erase(fittedTemplate.begin() + j);
        fittedMeasure.erase(fittedMeasure.begin() + j);
        j = i; // the joined surface against the rest again
      }
      if (self->CheckAbort())
      {
        return false;
      }
    }
  }
  if (fitted.empty())
  {
    return PassThrough("no surface could be fitted to the shock clusters (" + fitProblems.str() +
      "; see the messages above).");
  }
  if (!fitProblems.str().empty())
  {
    vtkWarningWithObjectMacro(self, << "AdaptToShocks: no surface was fitted to" << fitProblems.str()
                    << "; the other surfaces are used.");
  }
  return true;
}

//------------------------------------------------------------------------------
void AdaptRun::DropCrossing()
{
  // A surface that crosses a larger cluster's surface (e.g. a piece of the
  // same shock split off near its foot, or a second shock that meets the
  // first) cannot be embedded with it: it is left out, with a warning.
  auto arrays = [](vtkPolyData* pd, std::vector<double>& p, std::vector<std::int64_t>& t) {
    p.resize(3 * static_cast<std::size_t>(pd->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    {
      pd->GetPoint(i, &p[3 * i]);
    }
    t.clear();
    vtkIdType npts;
    const vtkIdType* ids;
    vtkCellArray* polys = pd->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
    {
      for (vtkIdType k = 1; k + 1 < npts; ++k)
      {
        t.insert(t.end(), { ids[0], ids[k], ids[k + 1] });
      }
    }
  };
  std::vector<std::vector<double>> pts(fitted.size());
  std::vector<std::vector<std::int64_t>> tris(fitted.size());
  for (std::size_t i = 0; i < fitted.size(); ++i)
  {
    arrays(fitted[i], pts[i], tris[i]);
  }
  std::vector<std::size_t> keptIndex;
  for (std::size_t i = 0; i < fitted.size(); ++i)
  {
    int crossed = -1;
    for (std::size_t j : keptIndex)
    {
      // (every rank decides the same: the surfaces live on rank 0 under MPI)
      double hit = ar::SurfacesIntersect(pts[j], tris[j], pts[i], tris[i]) ? 1.0 : 0.0;
      vtkARParallel::AllReduceMax(&hit, 1);
      if (hit > 0.0)
      {
        crossed = static_cast<int>(j);
        break;
      }
    }
    if (crossed >= 0)
    {
      // (a surface's first cluster is its largest)
      vtkWarningWithObjectMacro(self, << "AdaptToShocks: the surface of cluster " << fittedClusters[i][0] << " ("
                      << sizes[fittedClusters[i][0]] << " nodes) crosses the surface of cluster "
                      << fittedClusters[crossed][0] << " and is left out.");
      continue;
    }
    keptIndex.push_back(i);
  }
  std::vector<vtkSmartPointer<vtkPolyData>> kept;
  for (const std::size_t i : keptIndex)
  {
    kept.push_back(fitted[i]);
    fittedTemplate[kept.size() - 1] = fittedTemplate[i];
    fittedClusters[kept.size() - 1] = fittedClusters[i];
  }
  fitted = kept;
  fittedTemplate.resize(kept.size());
  fittedClusters.resize(kept.size());
}

//------------------------------------------------------------------------------
void AdaptRun::Append()
{
  // The kept surfaces, numbered, in one polydata; their templates.
  templates->SetName("SurfaceTemplates");
  members->SetName("SurfaceClusters");
  for (std::size_t i = 0; i < fitted.size(); ++i)
  {
    std::string list;
    for (const int k : fittedClusters[i])
    {
      list += (list.empty() ? "" : "+") + std::to_string(k);
    }
    members->InsertNextValue(list);
    vtkNew<vtkIntArray> id;
    id->SetName("SurfaceId");
    id->SetNumberOfTuples(fitted[i]->GetNumberOfCells());
    id->FillValue(static_cast<int>(i));
    fitted[i]->GetCellData()->AddArray(id);
    append->AddInputData(fitted[i]);
    templates->InsertNextValue(fittedTemplate[i]);
  }
  append->Update();
  secondsFit = Lap();
}

//------------------------------------------------------------------------------
void AdaptRun::GatherIfHybrid()
{
  // EmbeddedRemesh distributes tetrahedral meshes only: under MPI a hybrid
  // or one-cell-deep volume (the 2-D mode) is gathered to rank 0 and
  // remeshed there alone.
  ctrl = vtkMultiProcessController::GetGlobalController();
  const bool distributed = ctrl && ctrl->GetNumberOfProcesses() > 1;
  root = !ctrl || ctrl->GetLocalProcessId() == 0;
  remeshInput = input;
  alone = false;
  if (distributed && vtkUnstructuredGrid::SafeDownCast(input))
  {
    double other = 0.0;
    for (vtkIdType c = 0; c < volume->GetNumberOfCells() && other == 0.0; ++c)
    {
      other = volume->GetCellType(c) != VTK_TETRA ? 1.0 : 0.0;
    }
    vtkARParallel::AllReduceMax(&other, 1);
    if (other > 0.0)
    {
      alone = true;
      remeshInput = vtkARParallel::GatherVolumeOnRoot(volume);
      if (root)
      {
        vtkWarningWithObjectMacro(self, << "AdaptToShocks: the mesh is not tetrahedral (hybrid, or one cell deep): it is "
                           "gathered to rank 0 ("
                        << vtkUnstructuredGrid::SafeDownCast(remeshInput)->GetNumberOfCells()
                        << " cells) and remeshed there; the other ranks' outputs are empty.");
      }
    }
  }
}

//------------------------------------------------------------------------------
double AdaptRun::SurfacesShockThickness() const
{
  // QuadricFit's ShockThickness, the median over the surfaces (the fields
  // are on rank 0 under MPI). Collective.
  double thickness = 0.0;
  const double lowest = -std::numeric_limits<double>::max();
  std::vector<double> widths(fitted.size(), lowest);
  for (std::size_t i = 0; i < fitted.size(); ++i)
  {
    vtkDataArray* t = fitted[i]->GetFieldData()->GetArray("ShockThickness");
    widths[i] = t && t->GetNumberOfTuples() > 0 ? t->GetComponent(0, 0) : lowest;
  }
  if (!widths.empty())
  {
    vtkARParallel::AllReduceMax(widths.data(), static_cast<int>(widths.size()));
  }
  std::vector<double> positive;
  std::copy_if(widths.begin(), widths.end(), std::back_inserter(positive), [](double w) { return w > 0.0; });
  if (!positive.empty())
  {
    std::sort(positive.begin(), positive.end());
    thickness = positive[positive.size() / 2];
  }
  return thickness;
}

//------------------------------------------------------------------------------
bool AdaptRun::Remesh()
{
  // ---- 4. The remeshing with every surface embedded.
  GatherIfHybrid();
  vtkNew<vtkEmbeddedRemesh> remesh;
  remesh->SetInputData(remeshInput);
  for (const auto& s : fitted)
  {
    remesh->AddSurfaceData(s);
  }
  remesh->SetMode(self->GetMode());
  remesh->SetSurfaceEdgeLength(self->GetSurfaceEdgeLength());
  remesh->SetSurfaceSizeFactor(self->GetSurfaceSizeFactor());
  remesh->SetLayerType(self->GetLayerType());
  remesh->SetNumberOfLayers(self->GetNumberOfLayers());
  // The prism stack spans half the captured shock, a quarter of its
  // thickness per side, unless TotalThickness is given: the solver's shock
  // on the layers spans about seven of them (cone15Ma3), so thinner layers,
  // not a taller stack, make it sharper (README, the payoff).
  shockThickness = SurfacesShockThickness();
  remesh->SetTotalThickness(self->GetTotalThickness() > 0.0 ? self->GetTotalThickness() : 0.25 * shockThickness);
  remesh->SetGrowthRatio(self->GetGrowthRatio());
  remesh->SetRemovalFactor(self->GetRemovalFactor());
  remesh->SetInterpolateFields(self->GetInterpolateFields());
  if (!alone)
  {
    remesh->Update();
  }
  else if (root)
  {
    // EmbeddedRemesh runs its distributed path whenever the global
    // controller has several processes: for its run on rank 0 alone, the
    // global controller is one process, and is given back right after.
    vtkNew<vtkDummyController> one;
    vtkMultiProcessController::SetGlobalController(one);
    remesh->Update();
    vtkMultiProcessController::SetGlobalController(ctrl);
  }
  vtkDataObject* adapted = remesh->GetOutputDataObject(0);
  vtkUnstructuredGrid* adaptedVolume = vtkEmbeddedRemesh::VolumeLeaf(adapted);
  double remeshed = adaptedVolume && adaptedVolume->GetCellData()->GetArray("Region") ? 1.0 : 0.0;
  if (alone)
  {
    vtkARParallel::AllReduceMax(&remeshed, 1); // rank 0's
  }
  if (remeshed == 0.0)
  {
    return PassThrough("the remeshing failed (see EmbeddedRemesh's message above).");
  }
  if (alone)
  {
    // Every rank gets rank 0's field data (as EmbeddedRemesh's distributed
    // path gives it); the other ranks' meshes are empty.
    vtkNew<vtkUnstructuredGrid> empty;
    vtkARParallel::BroadcastFieldDataFromRoot(root ? adaptedVolume->GetFieldData() : empty->GetFieldData());
    if (!root)
    {
      output->ShallowCopy(empty);
      surfaces->ShallowCopy(append->GetOutput());
    }
  }
  secondsRemesh = Lap();
  if (!alone || root)
  {
    output->ShallowCopy(adapted);
    surfaces->ShallowCopy(append->GetOutput());
  }
  return true;
}

//------------------------------------------------------------------------------
void AdaptRun::Output()
{
  vtkUnstructuredGrid* outVolume = vtkUnstructuredGrid::SafeDownCast(output);
  outVolume = outVolume ? outVolume : vtkEmbeddedRemesh::VolumeLeaf(output);
  vtkFieldData* fd = outVolume->GetFieldData();
  const double count = static_cast<double>(fitted.size());
  fd->AddArray(vtkARMeshKernels::FieldArray("NumberOfSurfaces", &count, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("ShockThickness", &shockThickness, 1));
  fd->AddArray(templates);
  fd->AddArray(members);
  // Per cluster that got a surface, before the crossing check: its shock
  // normals' two families (angle, median spread in degrees, lighter
  // family's fraction), the two-shocks-meet check's measures.
  auto normalFamilies = vtkARMeshKernels::FieldArray("NormalFamilies", families.data(), static_cast<int>(families.size()));
  normalFamilies->SetNumberOfComponents(3);
  normalFamilies->SetNumberOfTuples(static_cast<vtkIdType>(chosen.size()));
  for (std::size_t i = 0; i < families.size(); ++i)
  {
    normalFamilies->SetValue(static_cast<vtkIdType>(i), families[i]);
  }
  fd->AddArray(normalFamilies);
  fd->AddArray(vtkARMeshKernels::FieldArray("SecondsSensor", &secondsSensor, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("SecondsClusters", &secondsClusters, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("SecondsFit", &secondsFit, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("SecondsRemesh", &secondsRemesh, 1));
}
}

//------------------------------------------------------------------------------
int vtkAdaptToShocks::ExecuteData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* input = vtkDataObject::GetData(inputVector[0], 0);
  vtkDataObject* output = vtkDataObject::GetData(outputVector, 0);
  vtkPolyData* surfaces = vtkPolyData::GetData(outputVector, 1);
  surfaces->Initialize();
  AdaptRun run(this, this->ClusterTemplates, input, output, surfaces);
  // Every rank runs every stage; a stage that fails has said why.
  auto proceed = [&](double progress, bool abortable) {
    this->UpdateProgress(progress);
    return !abortable || !this->CheckAbort();
  };
  if (!(run.Check() && run.Sense() && proceed(0.2, true) && run.Cluster() && proceed(0.35, true) &&
        run.FitEach() && run.JoinPieces()))
  {
    return 1;
  }
  run.DropCrossing();
  run.Append();
  this->UpdateProgress(0.5);
  if (run.Remesh())
  {
    run.Output();
    this->UpdateProgress(1.0);
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkAdaptToShocks::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Gamma: " << this->Gamma << "\n";
  os << indent << "GasConstant: " << this->GasConstant << "\n";
  os << indent << "SensorRange: " << this->SensorRange[0] << " " << this->SensorRange[1] << "\n";
  os << indent << "MinimumClusterSize: " << this->MinimumClusterSize << "\n";
  os << indent << "MinimumClusterFraction: " << this->MinimumClusterFraction << "\n";
  os << indent << "MaximumNumberOfSurfaces: " << this->MaximumNumberOfSurfaces << "\n";
  for (const auto& ct : this->ClusterTemplates)
  {
    os << indent << "ClusterTemplate " << ct.first << ": " << ct.second << "\n";
  }
  os << indent << "Mode: " << this->Mode << "\n";
  os << indent << "SurfaceEdgeLength: " << this->SurfaceEdgeLength << "\n";
  os << indent << "SurfaceSizeFactor: " << this->SurfaceSizeFactor << "\n";
  os << indent << "LayerType: " << this->LayerType << "\n";
  os << indent << "NumberOfLayers: " << this->NumberOfLayers << "\n";
  os << indent << "TotalThickness: " << this->TotalThickness << "\n";
  os << indent << "GrowthRatio: " << this->GrowthRatio << "\n";
  os << indent << "RemovalFactor: " << this->RemovalFactor << "\n";
  os << indent << "InterpolateFields: " << this->InterpolateFields << "\n";
}
